#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
#include "shaders/smoke_interface.h"

layout(location = 0) rayPayloadInEXT SmokeHit payload;

void main() {
  payload.hit = 0u;
  payload.t = -1.0;
  payload.primitive_id = 0xFFFFFFFFu;
  payload.custom_index = 0xFFFFFFFFu;
}
