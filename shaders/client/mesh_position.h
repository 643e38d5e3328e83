// Where a mesh vertex lands (GLSL; included by client/gbuffer.vert and client/shadow_depth.vert, so the G-buffer
// and the shadow maps rasterize the same positions). Camera-relative: positions are relative to their mesh's
// origin. A static mesh adds the push constant's (mesh origin - eye), computed in double on the CPU, and the
// view-projection has the eye at the origin; a moving mesh (kClientMeshMoves) gets its whole model-view-projection
// at the frame's scene time, composed in double on the CPU.
#ifndef DHR_MESH_POSITION_H
#define DHR_MESH_POSITION_H

#include "shaders/shader_interface.h"

vec4 mesh_clip_position(ClientGBufferPush pc, vec3 position) {
  const mat4 view_proj = mat4(pc.view_proj[0], pc.view_proj[1], pc.view_proj[2], pc.view_proj[3],
                              pc.view_proj[4], pc.view_proj[5], pc.view_proj[6], pc.view_proj[7],
                              pc.view_proj[8], pc.view_proj[9], pc.view_proj[10], pc.view_proj[11],
                              pc.view_proj[12], pc.view_proj[13], pc.view_proj[14], pc.view_proj[15]);
  if ((pc.flags & kClientMeshMoves) != 0u) return view_proj * vec4(position, 1.0);
  return view_proj * vec4(position + vec3(pc.mesh[0], pc.mesh[1], pc.mesh[2]), 1.0);
}

#endif  // DHR_MESH_POSITION_H
