#version 460
#extension GL_GOOGLE_include_directive : require
#include "shaders/shader_interface.h"

// Camera-relative rasterization: positions are relative to their mesh's origin. A static mesh adds the push
// constant's (mesh origin - eye), computed in double on the CPU, and the view-projection has the eye at the
// origin; a moving mesh (kClientMeshMoves) gets its whole model-view-projection at the frame's scene time, composed
// in double on the CPU, and its normals turned by the motion's normal matrix.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;  // world space (at rest)
layout(location = 2) in vec2 in_uv;

layout(push_constant, std430) uniform Push { ClientGBufferPush pc; };

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec2 out_uv;

void main() {
  const mat4 view_proj = mat4(pc.view_proj[0], pc.view_proj[1], pc.view_proj[2], pc.view_proj[3],
                              pc.view_proj[4], pc.view_proj[5], pc.view_proj[6], pc.view_proj[7],
                              pc.view_proj[8], pc.view_proj[9], pc.view_proj[10], pc.view_proj[11],
                              pc.view_proj[12], pc.view_proj[13], pc.view_proj[14], pc.view_proj[15]);
  if ((pc.flags & kClientMeshMoves) != 0u) {
    const mat3 normal_matrix = mat3(pc.mesh[0], pc.mesh[1], pc.mesh[2], pc.mesh[3], pc.mesh[4], pc.mesh[5],
                                    pc.mesh[6], pc.mesh[7], pc.mesh[8]);
    gl_Position = view_proj * vec4(in_position, 1.0);
    out_normal = normal_matrix * in_normal;  // the fragment shaders normalize
  } else {
    const vec3 p = in_position + vec3(pc.mesh[0], pc.mesh[1], pc.mesh[2]);
    gl_Position = view_proj * vec4(p, 1.0);
    out_normal = in_normal;
  }
  out_uv = in_uv;
}
