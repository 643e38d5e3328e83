#version 460
#extension GL_EXT_ray_tracing : require

// Shadow ray reached its end without hitting anything: the light is visible.
layout(location = 1) rayPayloadInEXT uint shadow_reached;

void main() { shadow_reached = 1u; }
