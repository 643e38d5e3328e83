#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
#include "visibility_payload.glsl"

// Primary ray missed everything: background pixel.
layout(location = 0) rayPayloadInEXT VisPrimaryPayload primary;

void main() { primary.mesh = kVisNoHit; }
