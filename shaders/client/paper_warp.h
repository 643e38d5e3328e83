// The paper's warp rule for one display pixel (GLSL; included by warp.comp and client/forward_body.h). The including
// shader declares `pc` (ClientWarpParams), `vis0` and `rows0` (source 0's masks and row validity) and v3().
// The CPU reference is render/warp_reference.cpp.
#ifndef DHR_PAPER_WARP_H
#define DHR_PAPER_WARP_H

// The paper's warp alone (no ingredient of WarpSettings on): the same decisions as warp.comp's look_up in its nearest case,
// branch-free, because SIMD CPU implementations (lavapipe) run both sides of a divergent branch: at 1832x1920
// the general path costs 1.7x this one for the paper's rule.
// centre: the pixel centre (i + 0.5, j + 0.5); d: its reversed-Z depth (0: background).
uint paper_warp(vec2 centre, float d, out uint mask, out vec2 motion) {
  const vec3 ray = v3(pc.source[0].ray0) + centre.x * v3(pc.source[0].ray_dx) + centre.y * v3(pc.source[0].ray_dy);
  const vec3 p_old = (pc.near_plane / d) * ray + v3(pc.source[0].trans);
  const float depth_old = -p_old.z;
  const float px = pc.source[0].old_px_scale * (p_old.x / depth_old) + pc.source[0].old_px_offset;
  const float py = pc.source[0].old_py_scale * (p_old.y / depth_old) + pc.source[0].old_py_offset;
  const uint w = pc.source[0].old_width, h = pc.source[0].old_height;
  const bool inside = px >= 0.0 && py >= 0.0 && px < float(w) && py < float(h);
  // Clamped, so the loads below stay in bounds whatever the decision (NaN included).
  const uint ix = min(uint(max(px, 0.0)), w - 1u);
  const uint iy = min(uint(max(py, 0.0)), h - 1u);
  const bool rows_ok = (pc.source[0].flags & kClientSourceHasRowValidity) == 0u || ((rows0[iy >> 5] >> (iy & 31u)) & 1u) != 0u;
  const uint bits = pc.source[0].mask_bits;
  const uint bit = (iy * w + ix) * bits;
  const uint width_mask = bits >= 32u ? 0xFFFFFFFFu : (1u << bits) - 1u;
  const uint old_mask = (vis0[bit >> 5] >> (bit & 31u)) & width_mask;
  const uint status = !(d > 0.0) ? kClientStatusBackground
                    : (pc.source[0].flags & kClientSourceHasVisibility) == 0u ? kClientStatusNoData
                    : !(depth_old > pc.min_depth) ? kClientStatusBehind
                    : !inside ? kClientStatusOutside
                    : !rows_ok ? kClientStatusMissingRow
                    : kClientStatusKnown;
  mask = status == kClientStatusKnown ? old_mask : pc.unknown_mask;
  const bool valid = status == kClientStatusKnown || status == kClientStatusOutside || status == kClientStatusMissingRow;
  const vec2 still = vec2(pc.ident_px_scale * centre.x + pc.ident_px_offset, pc.ident_py_scale * centre.y + pc.ident_py_offset);
  motion = valid ? vec2(px, py) - still : vec2(0.0);
  return status;
}

#endif  // DHR_PAPER_WARP_H
