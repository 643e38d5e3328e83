#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shader_interface.h"

// Warp (the paper's reprojection): each display pixel's surface point, reconstructed from this frame's depth,
// is projected into the old guard-banded camera the visibility buffer was traced for, and the old mask at
// the nearest pixel (floor of the continuous coordinate; centres at +0.5) is taken. Background, points at or
// behind the old eye plane, lookups outside the old buffer and rows that did not arrive are unknown and
// take all light bits ("taken as lit"). All positions are eye-relative: only small numbers reach the GPU.
// xrclient/render/warp_reference.cpp is the CPU reference; the decisions have the same precedence.
// Branch-free on purpose: SIMD CPU implementations (lavapipe) run both sides of a divergent branch.
layout(local_size_x = kClientWarpGroupSize, local_size_y = kClientWarpGroupSize) in;

layout(set = 0, binding = kClientWarpBindingDepth) uniform sampler2D depth_texture;
layout(set = 0, binding = kClientWarpBindingVisibility, std430) readonly buffer Visibility { uint vis_words[]; };
layout(set = 0, binding = kClientWarpBindingRowValid, std430) readonly buffer RowValid { uint row_words[]; };
layout(set = 0, binding = kClientWarpBindingMask, r32ui) uniform writeonly uimage2D mask_image;
layout(set = 0, binding = kClientWarpBindingStatus, r32ui) uniform writeonly uimage2D status_image;  // optional
layout(set = 0, binding = kClientWarpBindingMotion, rg32f) uniform writeonly image2D motion_image;
layout(set = 0, binding = kClientWarpBindingCounters, std430) buffer Counters { uint counters[]; };
layout(push_constant, std430) uniform Push { ClientWarpPush pc; };

vec3 v3(float a[3]) { return vec3(a[0], a[1], a[2]); }

void main() {
  const uvec2 id = gl_GlobalInvocationID.xy;
  const bool in_image = id.x < pc.width && id.y < pc.height;
  uint status = kClientStatusCount;  // outside the image: counted nowhere
  if (in_image) {
    const float d = texelFetch(depth_texture, ivec2(id), 0).r;
    const vec2 centre = vec2(id) + 0.5;
    const vec3 ray = v3(pc.ray0) + centre.x * v3(pc.ray_dx) + centre.y * v3(pc.ray_dy);
    const vec3 p_old = (pc.near_plane / d) * ray + v3(pc.trans);
    const float depth_old = -p_old.z;
    const float px = pc.old_px_scale * (p_old.x / depth_old) + pc.old_px_offset;
    const float py = pc.old_py_scale * (p_old.y / depth_old) + pc.old_py_offset;
    const bool inside = px >= 0.0 && py >= 0.0 && px < float(pc.old_width) && py < float(pc.old_height);
    // Clamped, so the loads below stay in bounds whatever the decision (NaN included).
    const uint ix = min(uint(max(px, 0.0)), pc.old_width - 1u);
    const uint iy = min(uint(max(py, 0.0)), pc.old_height - 1u);
    const bool row_ok = (pc.flags & kClientWarpHasRowValidity) == 0u ||
                        ((row_words[iy >> 5] >> (iy & 31u)) & 1u) != 0u;
    const uint bit = (iy * pc.old_width + ix) * pc.mask_bits;
    const uint width_mask = pc.mask_bits >= 32u ? 0xFFFFFFFFu : (1u << pc.mask_bits) - 1u;
    const uint old_mask = (vis_words[bit >> 5] >> (bit & 31u)) & width_mask;

    status = !(d > 0.0) ? kClientStatusBackground
           : (pc.flags & kClientWarpHasVisibility) == 0u ? kClientStatusNoData
           : !(depth_old > pc.min_depth) ? kClientStatusBehind
           : !inside ? kClientStatusOutside
           : !row_ok ? kClientStatusMissingRow
           : kClientStatusKnown;
    imageStore(mask_image, ivec2(id), uvec4(status == kClientStatusKnown ? old_mask : pc.unknown_mask, 0u, 0u, 0u));
    if ((pc.flags & kClientWarpWriteStatus) != 0u) {
      imageStore(status_image, ivec2(id), uvec4(status, 0u, 0u, 0u));
    }
    if ((pc.flags & kClientWarpWriteMotion) != 0u) {
      const vec2 still = vec2(pc.ident_px_scale * centre.x + pc.ident_px_offset,
                              pc.ident_py_scale * centre.y + pc.ident_py_offset);
      const bool valid = status == kClientStatusKnown || status == kClientStatusOutside ||
                         status == kClientStatusMissingRow;
      imageStore(motion_image, ivec2(id), vec4(valid ? vec2(px, py) - still : vec2(0.0), 0.0, 0.0));
    }
  }

  // Per-status counts: two subgroup sums of one-hot values packed in 10-bit fields, then the elected lane
  // adds them to its bucket (8 horizontally adjacent workgroups, at most 512 pixels: no field overflows); the
  // host unpacks and sums the buckets. Buckets instead of one counter per status: with every workgroup
  // hitting the same six words the atomics serialize (on lavapipe they cost a third of the pass).
  const uint one_hot = status < kClientStatusCount ? 1u << (10u * (status % 3u)) : 0u;
  const uint low = subgroupAdd(status < 3u ? one_hot : 0u);
  const uint high = subgroupAdd(status >= 3u ? one_hot : 0u);
  if (subgroupElect()) {
    const uint buckets_x = (gl_NumWorkGroups.x + kClientCountBucketGroups - 1u) / kClientCountBucketGroups;
    const uint bucket = 2u * (gl_WorkGroupID.y * buckets_x + gl_WorkGroupID.x / kClientCountBucketGroups);
    if (low != 0u) atomicAdd(counters[bucket], low);
    if (high != 0u) atomicAdd(counters[bucket + 1u], high);
  }
}
