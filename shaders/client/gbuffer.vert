#version 460
#extension GL_GOOGLE_include_directive : require
#include "shaders/shader_interface.h"

// Camera-relative rasterization: positions are relative to their mesh's origin, the push constant adds
// (mesh origin - eye) computed in double on the CPU, and the view-projection has the eye at the origin.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;  // world space
layout(location = 2) in vec2 in_uv;

layout(push_constant, std430) uniform Push { ClientGBufferPush pc; };

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec2 out_uv;

void main() {
  const mat4 view_proj = mat4(pc.view_proj[0], pc.view_proj[1], pc.view_proj[2], pc.view_proj[3],
                              pc.view_proj[4], pc.view_proj[5], pc.view_proj[6], pc.view_proj[7],
                              pc.view_proj[8], pc.view_proj[9], pc.view_proj[10], pc.view_proj[11],
                              pc.view_proj[12], pc.view_proj[13], pc.view_proj[14], pc.view_proj[15]);
  const vec3 p = in_position + vec3(pc.translation_x, pc.translation_y, pc.translation_z);
  gl_Position = view_proj * vec4(p, 1.0);
  out_normal = in_normal;
  out_uv = in_uv;
}
