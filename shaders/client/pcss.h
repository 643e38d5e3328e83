// Percentage-closer soft shadows on the client's cube shadow maps (GLSL; included by client/shadow_lookup.h after
// the face lookup, client/cube_face.h). The CPU reference is render/pcss_reference.cpp. For a light with
// an extent (representative radius R, ClientShadowLight::radius), at a receiver at distance d along the cube
// face's axis, lookup at continuous texel position c on face `face`, texels per tangent unit s = size / 2:
//   1. Blocker search: kClientPcssSearchGrid^2 taps on a regular grid (cell centres) of radius
//      r_s = R / d * s texels (the penumbra of a blocker halfway to the light), clamped to
//      [kClientPcssMinRadius, kClientPcssMaxRadius]; a tap whose stored occluder is nearer than the receiver
//      less the bias is a blocker. No blocker: fully lit (1).
//   2. Penumbra by similar triangles from the blockers' mean distance z: w = R (d - z) / z metres at the receiver,
//      r_f = w / d * s texels, clamped as above.
//   3. PCF: kClientPcssFilterGrid^2 taps on a regular grid of radius r_f; the fraction of unblocked taps.
// The bias grows with the footprint (a tilted receiver's depth varies over it): the hard lookup's slope term
// (bias_slope texels) plus sqrt(2) x radius texels, times tan(N, L).
#ifndef DHR_PCSS_H
#define DHR_PCSS_H

#include "shaders/shader_interface.h"

// Grid tap k (of g per axis) over [-radius, radius]: the centre of cell k.
float pcss_grid(uint k, uint g, float radius) { return radius * ((2.0 * float(k) + 1.0) / float(g) - 1.0); }

float pcss_radius(float r) { return clamp(r, kClientPcssMinRadius, kClientPcssMaxRadius); }

// The stored occluder distance (along the face axis) of texel t, clamped to the face (3e38: nothing).
float pcss_occluder(sampler2D atlas, uint size, float near_plane, uint row, uint face, ivec2 t) {
  const ivec2 c = clamp(t, ivec2(0), ivec2(int(size) - 1));
  const float stored = texelFetch(atlas, ivec2(face * size + uint(c.x), row * size + uint(c.y)), 0).r;
  return stored > 0.0 ? near_plane / stored : 3.0e38;
}

// The share of the light the point sees. distance: the receiver's distance along the face axis; base_bias: the
// hard lookup's bias without its slope term; slope: texel (world, at the point) x tan(N, L).
float pcss_fraction(ClientWarpParams params, sampler2D atlas, uint row, uint face, vec2 position, float distance,
                    float radius, float base_bias, float slope) {
  const uint size = params.shadow_size;
  const float s = 0.5 * float(size);
  const float search_radius = pcss_radius(radius / distance * s);
  const float search_threshold =
      distance - (base_bias + (params.shadow_bias_slope + 1.41421356 * search_radius) * slope);
  float blocker_sum = 0.0;
  uint blockers = 0u;
  for (uint k = 0u; k < kClientPcssSearchGrid * kClientPcssSearchGrid; ++k) {
    const vec2 q = position + vec2(pcss_grid(k % kClientPcssSearchGrid, kClientPcssSearchGrid, search_radius),
                                   pcss_grid(k / kClientPcssSearchGrid, kClientPcssSearchGrid, search_radius));
    const float z = pcss_occluder(atlas, size, params.shadow_near, row, face, ivec2(floor(q)));
    if (z < search_threshold) {
      blocker_sum += z;
      ++blockers;
    }
  }
  if (blockers == 0u) return 1.0;
  const float z = blocker_sum / float(blockers);
  const float pcf_radius = pcss_radius(radius * (distance - z) / (z * distance) * s);
  const float threshold = distance - (base_bias + (params.shadow_bias_slope + 1.41421356 * pcf_radius) * slope);
  uint lit = 0u;
  for (uint k = 0u; k < kClientPcssFilterGrid * kClientPcssFilterGrid; ++k) {
    const vec2 q = position + vec2(pcss_grid(k % kClientPcssFilterGrid, kClientPcssFilterGrid, pcf_radius),
                                   pcss_grid(k / kClientPcssFilterGrid, kClientPcssFilterGrid, pcf_radius));
    if (pcss_occluder(atlas, size, params.shadow_near, row, face, ivec2(floor(q))) >= threshold) ++lit;
  }
  return float(lit) / float(kClientPcssFilterGrid * kClientPcssFilterGrid);
}

#endif  // DHR_PCSS_H
