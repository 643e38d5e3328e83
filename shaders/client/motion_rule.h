// The warp's motion rule (kClientWarpMotion; shader_interface.h's ClientWarpMotion says what it decides and why),
// included by warp.comp and forward_body.h after `pc` (ClientWarpParams) is declared; they define
// DHR_MOTION_BUFFER_SET and DHR_MOTION_BUFFER_BINDING, where its ClientWarpMotion buffer is. The CPU reference is
// render/warp_motion.cpp's motion_unknown_bits (double; the same tests in the same order).
#ifndef DHR_CLIENT_MOTION_RULE_H
#define DHR_CLIENT_MOTION_RULE_H

#if !defined(DHR_MOTION_BUFFER_SET) || !defined(DHR_MOTION_BUFFER_BINDING)
#error "define DHR_MOTION_BUFFER_SET and DHR_MOTION_BUFFER_BINDING before including client/motion_rule.h"
#endif
layout(set = DHR_MOTION_BUFFER_SET, binding = DHR_MOTION_BUFFER_BINDING, std430) restrict readonly buffer Moved {
  ClientWarpMotion moved;
};

bool motion_box_contains(uint s, uint b, vec3 p, float grow) {
  const uint i = 3u * b;
  const vec3 lo = vec3(moved.source[s].box_min[i], moved.source[s].box_min[i + 1u],
                       moved.source[s].box_min[i + 2u]) - grow;
  const vec3 hi = vec3(moved.source[s].box_max[i], moved.source[s].box_max[i + 1u],
                       moved.source[s].box_max[i + 2u]) + grow;
  return all(greaterThanEqual(p, lo)) && all(lessThanEqual(p, hi));
}

// The segment a -> b meets box b of source s grown by `grow` (slab test).
bool motion_segment_hits(uint s, uint b, vec3 a, vec3 e, float grow) {
  const uint i = 3u * b;
  const vec3 lo = vec3(moved.source[s].box_min[i], moved.source[s].box_min[i + 1u],
                       moved.source[s].box_min[i + 2u]) - grow;
  const vec3 hi = vec3(moved.source[s].box_max[i], moved.source[s].box_max[i + 1u],
                       moved.source[s].box_max[i + 2u]) + grow;
  const vec3 d = e - a;
  float t_lo = 0.0, t_hi = 1.0;
  for (int k = 0; k < 3; ++k) {
    if (abs(d[k]) < 1e-30) {
      if (a[k] < lo[k] || a[k] > hi[k]) return false;
      continue;
    }
    float t0 = (lo[k] - a[k]) / d[k];
    float t1 = (hi[k] - a[k]) / d[k];
    if (t0 > t1) {
      const float t = t0;
      t0 = t1;
      t1 = t;
    }
    t_lo = max(t_lo, t0);
    t_hi = min(t_hi, t1);
    if (t_lo > t_hi) return false;
  }
  return true;
}

// The mask bits that motion since source s's scene time may have changed at the surface point p (display-eye
// relative, world axes); 0 when nothing moved.
uint motion_unknown_bits(uint s, vec3 p) {
  if (moved.enabled == 0u) return 0u;
  uint bits = moved.source[s].moved_bits;
  const uint boxes = moved.source[s].box_count;
  if (boxes > kClientMaxMotionBoxes) return pc.unknown_mask;
  for (uint b = 0u; b < boxes; ++b) {
    if (motion_box_contains(s, b, p, moved.receiver_margin)) return pc.unknown_mask;
  }
  for (uint l = 0u; l < pc.light_count && boxes > 0u; ++l) {
    const uint field = moved.light[l].field;
    if ((bits & field) == field) continue;
    const vec3 to = v3(moved.light[l].to_light);
    const bool directional = moved.light[l].directional != 0u;
    const vec3 e = directional ? p + moved.far_distance * to : to;
    const float grow = directional ? moved.light[l].growth * moved.far_distance : moved.light[l].growth;
    for (uint b = 0u; b < boxes; ++b) {
      if (motion_segment_hits(s, b, p, e, grow)) {
        bits |= field;
        break;
      }
    }
  }
  return bits & pc.unknown_mask;
}

#endif  // DHR_CLIENT_MOTION_RULE_H
