// The paper's warp rule for one display pixel (GLSL; included by warp.comp and client/forward_body.h). The CPU
// reference is render/warp_reference.cpp. Everything comes as arguments: the warp's parameters
// (ClientWarpParams: source 0, the display rays, min_depth, unknown_mask, ident_*) and the two words of source
// 0's buffers the pixel needs, which the shader loads between the two steps:
//   const PaperWarpLookup at = paper_warp_lookup(params, centre, d);
//   const uint row_word = paper_warp_reads_rows(params) ? rows0[at.row >> 5] : 0u;
//   status = paper_warp(params, centre, d, at, row_word, vis0[at.mask_bit >> 5], mask, motion);
#ifndef DHR_PAPER_WARP_H
#define DHR_PAPER_WARP_H

#include "shaders/shader_interface.h"
#include "client/float3.h"

// The paper's warp alone (no ingredient of WarpSettings on): the same decisions as warp.comp's look_up in its
// nearest case, branch-free, because SIMD CPU implementations (lavapipe) run both sides of a divergent branch: at
// 1832x1920 the general path costs 1.7x this one for the paper's rule.

// Where source 0's old buffer sees a display pixel.
struct PaperWarpLookup {
  vec2 pixel;        // continuous lookup coordinate in the old buffer
  float depth_old;   // the surface point's depth in the old eye
  uint row;          // the old pixel under the lookup, clamped into the buffer so that the loads stay in
  uint mask_bit;     //   bounds whatever the decision (NaN included): its row, its mask's first bit

};

// centre: the pixel centre (i + 0.5, j + 0.5); d: its reversed-Z depth (0: background).
PaperWarpLookup paper_warp_lookup(ClientWarpParams params, vec2 centre, float d) {
  const ClientWarpSource src = params.source[0];
  const vec3 ray = v3(src.ray0) + centre.x * v3(src.ray_dx) + centre.y * v3(src.ray_dy);
  const vec3 p_old = (params.near_plane / d) * ray + v3(src.trans);
  PaperWarpLookup at;
  at.depth_old = -p_old.z;
  at.pixel = vec2(src.old_px_scale * (p_old.x / at.depth_old) + src.old_px_offset,
                  src.old_py_scale * (p_old.y / at.depth_old) + src.old_py_offset);
  const uint column = min(uint(max(at.pixel.x, 0.0)), src.old_width - 1u);
  at.row = min(uint(max(at.pixel.y, 0.0)), src.old_height - 1u);
  at.mask_bit = (at.row * src.old_width + column) * src.mask_bits;
  return at;
}

// Whether the decision reads source 0's row validity (else its buffer need not be read).
bool paper_warp_reads_rows(ClientWarpParams params) {
  return (params.source[0].flags & kClientSourceHasRowValidity) != 0u;
}

// The decision: returns the status, sets the mask and the motion vector. row_word: word at.row >> 5 of source 0's
// row validity (any value when paper_warp_reads_rows is false); mask_word: word at.mask_bit >> 5 of its masks.
uint paper_warp(ClientWarpParams params, vec2 centre, float d, PaperWarpLookup at, uint row_word, uint mask_word,
                out uint mask, out vec2 motion) {
  const ClientWarpSource src = params.source[0];
  const float px = at.pixel.x, py = at.pixel.y;
  const uint w = src.old_width, h = src.old_height;
  const bool inside = px >= 0.0 && py >= 0.0 && px < float(w) && py < float(h);
  const bool rows_ok = !paper_warp_reads_rows(params) || ((row_word >> (at.row & 31u)) & 1u) != 0u;
  const uint bits = src.mask_bits;
  const uint width_mask = bits >= 32u ? 0xFFFFFFFFu : (1u << bits) - 1u;
  const uint old_mask = (mask_word >> (at.mask_bit & 31u)) & width_mask;
  const uint status = !(d > 0.0) ? kClientStatusBackground
                    : (src.flags & kClientSourceHasVisibility) == 0u ? kClientStatusNoData
                    : !(at.depth_old > params.min_depth) ? kClientStatusBehind
                    : !inside ? kClientStatusOutside
                    : !rows_ok ? kClientStatusMissingRow
                    : kClientStatusKnown;
  mask = status == kClientStatusKnown ? old_mask : params.unknown_mask;
  const bool valid = status == kClientStatusKnown || status == kClientStatusOutside || status == kClientStatusMissingRow;
  const vec2 still = vec2(params.ident_px_scale * centre.x + params.ident_px_offset,
                          params.ident_py_scale * centre.y + params.ident_py_offset);
  motion = valid ? vec2(px, py) - still : vec2(0.0);
  return status;
}

#endif  // DHR_PAPER_WARP_H
