#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shaders/shader_interface.h"

// Counts the forward pass's per-pixel statuses (kClientStatus*, background where nothing was drawn) into the
// warp pass's counter layout (warp.comp: 10-bit fields, three per word, one subgroup sum per word and one
// atomic per bucket of kClientCountBucketGroups workgroups), so WarpCounts reads both alike. With `fills` it
// also counts the shadow-map flags (kClientForwardStatusShadow*); without, only the words statuses 0-5 fill (the paper's warp has no disoccluded status)
// (a subgroup sum each costs on lavapipe).
layout(local_size_x = kClientWarpGroupSize, local_size_y = kClientWarpGroupSize) in;
layout(set = 0, binding = 0, r8ui) uniform readonly uimage2D status_image;
layout(set = 0, binding = 1, std430) buffer Counters { uint counters[]; };
layout(push_constant, std430) uniform Push { uint width; uint height; uint fills; } pc;

void main() {
  const uvec2 id = gl_GlobalInvocationID.xy;
  uint words[kClientCountWords];
  for (uint w = 0u; w < kClientCountWords; ++w) words[w] = 0u;
  if (id.x < pc.width && id.y < pc.height) {
    const uint value = imageLoad(status_image, ivec2(id)).x;
    const uint status = value & kClientForwardStatusMask;
    // kClientStatusDisoccluded (word 2) occurs only with `fills` (kServerEdges with the depth test).
    if (status < kClientStatusCount) words[status / 3u] += 1u << (10u * (status % 3u));
    if ((value & kClientForwardStatusShadowFill) != 0u) {
      words[kClientCountShadowMap / 3u] += 1u << (10u * (kClientCountShadowMap % 3u));
    }
    if ((value & kClientForwardStatusShadowEdge) != 0u) {
      words[kClientCountEdgeShadowMap / 3u] += 1u << (10u * (kClientCountEdgeShadowMap % 3u));
    }
    if ((value & kClientForwardStatusMotion) != 0u) {
      words[kClientCountMotion / 3u] += 1u << (10u * (kClientCountMotion % 3u));
    }
  }
  const uint used_words = pc.fills != 0u ? kClientCountMotion / 3u + 1u : 2u;  // dynamically uniform
  uint sums[kClientCountWords];
  for (uint w = 0u; w < kClientCountWords; ++w) sums[w] = w < used_words ? subgroupAdd(words[w]) : 0u;
  if (subgroupElect()) {
    const uint buckets_x = (gl_NumWorkGroups.x + kClientCountBucketGroups - 1u) / kClientCountBucketGroups;
    const uint bucket = kClientCountWords * (gl_WorkGroupID.y * buckets_x + gl_WorkGroupID.x / kClientCountBucketGroups);
    for (uint w = 0u; w < used_words; ++w) {
      if (sums[w] != 0u) atomicAdd(counters[bucket + w], sums[w]);
    }
  }
}
