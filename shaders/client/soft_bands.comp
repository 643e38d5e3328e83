#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "shaders/shader_interface.h"

// Band shares on the GPU (render/soft_band_pass.hpp): render/soft_bands.hpp's table of a received buffer, the same
// definition and the same bytes as its CPU soft_band_table (integers; the one quotient through a float, corrected to
// exact). One invocation per cell, three stages (ClientSoftBandPush::stage), a barrier between them:
//  - kClientSoftBandCount: per refined field, the cell's histogram of levels over its arrived pixels, as eight
//    lanes (lane 0 the pixels, lane k those at level k or above) and a byte of the levels held;
//  - kClientSoftBandRowSum: the lanes summed over the cells of its row within `reach`;
//  - kClientSoftBandShares: those summed over the cells of its column within `reach` (the window), and per level the
//    cell holds, the band share's byte (kClientSoftRefineNone for the bottom and top levels and fields without).
// A window holds at most 255^2 pixels (soft_bands.hpp), so lanes packed two to a word never carry into each other.
layout(local_size_x = kClientWarpGroupSize, local_size_y = kClientWarpGroupSize) in;
layout(set = 0, binding = kClientSoftBandBindingVisibility, std430) buffer Visibility { uint vis[]; };
layout(set = 0, binding = kClientSoftBandBindingRows, std430) readonly buffer Rows { uint rows[]; };
layout(set = 0, binding = kClientSoftBandBindingScratch, std430) buffer Scratch { uint scratch[]; };
layout(push_constant, std430) uniform Push { ClientSoftBandPush pc; };

// Lane k of a field's counts (0 beyond the top level).
uint lane(uvec4 counts, uint k) { return k > 7u ? 0u : (counts[k >> 1u] >> (16u * (k & 1u))) & 0xFFFFu; }

// The band share's byte of a pixel at level n whose window's lanes are `win`: soft_bands.cpp's share_byte.
uint share_byte(uvec4 win, uint n) {
  const uint from_below = lane(win, n > 0u ? n - 1u : 0u), at_n = lane(win, n);
  const uint above = lane(win, n + 1u), beyond = lane(win, n + 2u);
  const uint below = n > 0u ? from_below - at_n : 0u;
  const uint near = from_below - beyond;
  const uint top = kClientSoftLevels - 1u;
  uint twice = 2u * n, d = 1u;  // twice the mean, over d: the level itself when no pixel is within one level
  if (near > 0u) {
    const int s = 2 * (int(n * near) + int(above - beyond) - int(below));
    const int lo = max(0, int((2u * n) * near) - int(near)), hi = min(int(2u * top * near), int((2u * n + 1u) * near));
    twice = uint(clamp(s, lo, hi));
    d = near;
  }
  // The integer quotient through a float one (no vector integer division on many devices), corrected to exact: the
  // float's error is far below one at these magnitudes (quotients up to 254).
  const uint num = twice * kClientSoftRefineScale + top * d, den = 2u * top * d;
  uint q = uint(float(num) / float(den));
  if (q * den > num) --q;
  if ((q + 1u) * den <= num) ++q;
  return q;
}

void main() {
  const uvec2 cell = gl_GlobalInvocationID.xy;
  if (cell.x >= pc.columns || cell.y >= pc.rows) return;
  const uint index = cell.y * pc.columns + cell.x;
  // Per refined field its lanes, two to a component (loops over the fields unrolled: no array in memory).
  uvec4 sums[kClientSoftRefineFields];
  [[unroll]] for (uint r = 0u; r < kClientSoftRefineFields; ++r) sums[r] = uvec4(0u);

  if (pc.stage == kClientSoftBandCount) {
    const uint c = 1u << pc.cell_shift;
    const uint x0 = cell.x * c, y0 = cell.y * c;
    const uint width_mask = pc.mask_bits >= 32u ? 0xFFFFFFFFu : (1u << pc.mask_bits) - 1u;
    uint held = 0u;
    for (uint y = y0; y < min(pc.height, y0 + c); ++y) {
      if (pc.has_rows != 0u && ((rows[y >> 5u] >> (y & 31u)) & 1u) == 0u) continue;
      for (uint x = x0; x < min(pc.width, x0 + c); ++x) {
        const uint bit = (y * pc.width + x) * pc.mask_bits;
        const uint mask = (vis[bit >> 5u] >> (bit & 31u)) & width_mask;
        [[unroll]] for (uint r = 0u; r < kClientSoftRefineFields; ++r) {
          if (((pc.refined >> r) & 1u) == 0u) continue;
          const uint g = (mask >> pc.field_offset[r]) & 7u;
          const uint n = g ^ (g >> 1u) ^ (g >> 2u);  // Gray decode (3 bits)
          // Lane k counts the pixels at level k or above (lane 0: all arrived pixels).
          sums[r] += uvec4(lessThanEqual(uvec4(0u, 2u, 4u, 6u), uvec4(n))) +
                     (uvec4(lessThanEqual(uvec4(1u, 3u, 5u, 7u), uvec4(n))) << 16u);
          held |= 1u << (8u * r + n);
        }
      }
    }
    [[unroll]] for (uint r = 0u; r < kClientSoftRefineFields; ++r) {
      [[unroll]] for (uint j = 0u; j < 4u; ++j) scratch[index * kClientSoftBandCountWords + 4u * r + j] = sums[r][j];
    }
    scratch[index * kClientSoftBandCountWords + kClientSoftBandLaneWords] = held;
    return;
  }

  if (pc.stage == kClientSoftBandRowSum) {
    const uint first = cell.x >= pc.reach ? cell.x - pc.reach : 0u, last = min(pc.columns - 1u, cell.x + pc.reach);
    for (uint x = first; x <= last; ++x) {
      const uint from = (cell.y * pc.columns + x) * kClientSoftBandCountWords;
      [[unroll]] for (uint r = 0u; r < kClientSoftRefineFields; ++r) {
        if (((pc.refined >> r) & 1u) == 0u) continue;
        sums[r] += uvec4(scratch[from + 4u * r], scratch[from + 4u * r + 1u], scratch[from + 4u * r + 2u],
                         scratch[from + 4u * r + 3u]);
      }
    }
    [[unroll]] for (uint r = 0u; r < kClientSoftRefineFields; ++r) {
      [[unroll]] for (uint j = 0u; j < 4u; ++j) {
        scratch[pc.sum_word + index * kClientSoftBandLaneWords + 4u * r + j] = sums[r][j];
      }
    }
    return;
  }

  // Only the fields with a middle level in this cell have shares (the top and bottom levels keep theirs,
  // soft_bands.cpp): their window sums alone are read.
  const uint held = scratch[index * kClientSoftBandCountWords + kClientSoftBandLaneWords];
  uint with_shares = 0u;
  [[unroll]] for (uint r = 0u; r < kClientSoftRefineFields; ++r) {
    const uint middle = ((1u << (kClientSoftLevels - 1u)) - 2u) << (8u * r);  // levels 1 .. top - 1
    if (((pc.refined >> r) & 1u) != 0u && (held & middle) != 0u) with_shares |= 1u << r;
  }
  const uint first = cell.y >= pc.reach ? cell.y - pc.reach : 0u, last = min(pc.rows - 1u, cell.y + pc.reach);
  for (uint y = first; y <= last && with_shares != 0u; ++y) {
    const uint from = pc.sum_word + (y * pc.columns + cell.x) * kClientSoftBandLaneWords;
    [[unroll]] for (uint r = 0u; r < kClientSoftRefineFields; ++r) {
      if (((with_shares >> r) & 1u) == 0u) continue;
      sums[r] += uvec4(scratch[from + 4u * r], scratch[from + 4u * r + 1u], scratch[from + 4u * r + 2u],
                       scratch[from + 4u * r + 3u]);
    }
  }
  [[unroll]] for (uint r = 0u; r < kClientSoftRefineFields; ++r) {
    uvec2 words = uvec2(kClientSoftRefineNoneAll);
    if (((with_shares >> r) & 1u) != 0u) {
      for (uint n = 1u; n + 1u < kClientSoftLevels; ++n) {
        if (((held >> (8u * r + n)) & 1u) == 0u) continue;
        const uint shift = 8u * (n % 4u);
        words[n / 4u] = (words[n / 4u] & ~(0xFFu << shift)) | (share_byte(sums[r], n) << shift);
      }
    }
    vis[pc.share_word + index * kClientSoftBandCellWords + 2u * r] = words.x;
    vis[pc.share_word + index * kClientSoftBandCellWords + 2u * r + 1u] = words.y;
  }
}
