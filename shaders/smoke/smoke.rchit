#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
#include "shaders/smoke_interface.h"

layout(location = 0) rayPayloadInEXT SmokeHit payload;

void main() {
  payload.hit = 1u;
  payload.t = gl_HitTEXT;
  payload.primitive_id = uint(gl_PrimitiveID);
  payload.custom_index = uint(gl_InstanceCustomIndexEXT);
}
