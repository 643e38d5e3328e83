#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
#include "visibility_payload.glsl"

// Primary rays only (shadow rays skip closest-hit shaders): report the hit; the raygen shader rebuilds the
// surface point from the scene-relative vertices, exactly as the Embree backend does.
layout(location = 0) rayPayloadInEXT VisPrimaryPayload primary;
hitAttributeEXT vec2 barycentrics;

void main() {
  primary.mesh = uint(gl_InstanceCustomIndexEXT);
  primary.primitive = uint(gl_PrimitiveID);
  primary.u = barycentrics.x;
  primary.v = barycentrics.y;
}
