#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shaders/shader_interface.h"

// Counts the forward pass's per-pixel statuses (kClientStatus*, background where nothing was drawn) into the
// warp pass's counter layout (warp.comp: 10-bit fields, three per word, one subgroup sum per word and one
// atomic per bucket of kClientCountBucketGroups workgroups), so WarpCounts reads both alike.
layout(local_size_x = kClientWarpGroupSize, local_size_y = kClientWarpGroupSize) in;
layout(set = 0, binding = 0, r8ui) uniform readonly uimage2D status_image;
layout(set = 0, binding = 1, std430) buffer Counters { uint counters[]; };
layout(push_constant, std430) uniform Push { uint width; uint height; } pc;

void main() {
  const uvec2 id = gl_GlobalInvocationID.xy;
  uint words[2];
  words[0] = 0u;
  words[1] = 0u;
  if (id.x < pc.width && id.y < pc.height) {
    const uint status = imageLoad(status_image, ivec2(id)).x & 0xFFu;
    if (status < 6u) words[status / 3u] += 1u << (10u * (status % 3u));
  }
  const uint s0 = subgroupAdd(words[0]);
  const uint s1 = subgroupAdd(words[1]);
  if (subgroupElect()) {
    const uint buckets_x = (gl_NumWorkGroups.x + kClientCountBucketGroups - 1u) / kClientCountBucketGroups;
    const uint bucket = kClientCountWords * (gl_WorkGroupID.y * buckets_x + gl_WorkGroupID.x / kClientCountBucketGroups);
    if (s0 != 0u) atomicAdd(counters[bucket], s0);
    if (s1 != 0u) atomicAdd(counters[bucket + 1u], s1);
  }
}
