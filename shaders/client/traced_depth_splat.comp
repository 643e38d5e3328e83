#version 460
#extension GL_GOOGLE_include_directive : require
#include "shaders/shader_interface.h"

// The traced camera's depth without a raster pass (render/traced_depth_splat.hpp): each surface pixel of a display
// frame's depth (reversed-Z, depth = near / distance along the view axis) is moved into the traced depth camera's
// eye and written to the texel that contains its projection, keeping the nearest surface per texel (the largest
// reversed-Z depth: atomicMax on the float's bits, which order as unsigned integers for positive floats). Texels no
// pixel reaches keep 0 (no surface: the warp's depth test does not use their samples).
layout(local_size_x = kClientWarpGroupSize, local_size_y = kClientWarpGroupSize) in;
layout(set = 0, binding = 0) uniform sampler2D source_depth;
layout(set = 0, binding = 1, std430) buffer Target { uint target[]; };
layout(push_constant, std430) uniform Push {
  vec4 rot_x;       // rows of the rotation from the source eye to the target eye (xyz)
  vec4 rot_y;
  vec4 rot_z;
  vec4 trans;       // the source eye's origin in the target eye (xyz)
  vec4 source_tan;  // source: tangent at the left edge, at the top edge, tangent per pixel along x and y
  vec4 target_tan;  // target: the same four
  uvec4 size;       // source width, height; target width, height
  float near_plane;
} pc;

void main() {
  const ivec2 id = ivec2(gl_GlobalInvocationID.xy);
  if (id.x >= int(pc.size.x) || id.y >= int(pc.size.y)) return;
  const float d = texelFetch(source_depth, id, 0).r;
  if (!(d > 0.0)) return;  // background
  const float z = pc.near_plane / d;
  const vec3 p = vec3((pc.source_tan.x + (float(id.x) + 0.5) * pc.source_tan.z) * z,
                      (pc.source_tan.y - (float(id.y) + 0.5) * pc.source_tan.w) * z, -z);
  const vec3 q = vec3(dot(pc.rot_x.xyz, p), dot(pc.rot_y.xyz, p), dot(pc.rot_z.xyz, p)) + pc.trans.xyz;
  const float zt = -q.z;
  if (!(zt > pc.near_plane)) return;  // behind the traced camera's near plane
  const float px = (q.x / zt - pc.target_tan.x) / pc.target_tan.z;
  const float py = (pc.target_tan.y - q.y / zt) / pc.target_tan.w;
  if (!(px >= 0.0 && py >= 0.0 && px < float(pc.size.z) && py < float(pc.size.w))) return;
  const uint x = min(uint(px), pc.size.z - 1u), y = min(uint(py), pc.size.w - 1u);
  atomicMax(target[y * pc.size.z + x], floatBitsToUint(pc.near_plane / zt));
}
