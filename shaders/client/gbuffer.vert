#version 460
#extension GL_GOOGLE_include_directive : require
#include "shaders/shader_interface.h"
#include "client/mesh_position.h"

// The G-buffer's (and the forward pass's) vertices: the position (client/mesh_position.h), the world normal and
// the texture coordinate. A moving mesh's normals are turned by the motion's normal matrix.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;  // world space (at rest)
layout(location = 2) in vec2 in_uv;

layout(push_constant, std430) uniform Push { ClientGBufferPush pc; };

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec2 out_uv;

void main() {
  gl_Position = mesh_clip_position(pc, in_position);
  if ((pc.flags & kClientMeshMoves) != 0u) {
    const mat3 normal_matrix = mat3(pc.mesh[0], pc.mesh[1], pc.mesh[2], pc.mesh[3], pc.mesh[4], pc.mesh[5],
                                    pc.mesh[6], pc.mesh[7], pc.mesh[8]);
    out_normal = normal_matrix * in_normal;  // the fragment shaders normalize
  } else {
    out_normal = in_normal;
  }
  out_uv = in_uv;
}
