// Percentage-closer soft shadows on the client's shadow maps (GLSL; included by client/shadow_lookup.h). The CPU
// reference is render/pcss_reference.cpp. For a light with an extent (representative radius R,
// ClientShadowLight::radius), at a receiver at distance d along the cube face's axis, lookup at continuous texel
// position c on face `face`, texels per tangent unit s = size / 2 (a sun's orthographic map: below):
//   1. Blocker search: kClientPcssSearchGrid^2 taps on a regular grid (cell centres) of radius
//      r_s = R / d * s texels (the penumbra of a blocker halfway to the light), clamped to
//      [kClientPcssMinRadius, kClientPcssMaxRadius]; a tap whose stored occluder is nearer than the receiver
//      less the bias is a blocker. No blocker: fully lit (1).
//   2. Penumbra by similar triangles from the blockers' mean distance z: w = R (d - z) / z metres at the receiver,
//      r_f = w / d * s texels, clamped as above.
//   3. PCF: kClientPcssFilterGrid^2 taps on a regular grid of radius r_f; the fraction of unblocked taps.
// A sun (tan t of its angular radius, texel size x metres): search radius d t / x (blockers anywhere up to the
// map's near plane), penumbra (d - z) t / x texels.
// The bias grows with the footprint (a tilted receiver's depth varies over it): the hard lookup's slope term
// (bias_slope texels) plus sqrt(2) x radius texels, times tan(N, L).
#ifndef DHR_PCSS_H
#define DHR_PCSS_H

#include "shaders/shader_interface.h"
#include "client/shadow_texel.h"

// Grid tap k (of g per axis) over [-radius, radius]: the centre of cell k.
float pcss_grid(uint k, uint g, float radius) { return radius * ((2.0 * float(k) + 1.0) / float(g) - 1.0); }

float pcss_radius(float r) { return clamp(r, kClientPcssMinRadius, kClientPcssMaxRadius); }

// The share of the light the point sees. distance: the receiver's distance along the map's axis; scale: texels
// per unit of the similar-triangles term (cube: R / d x size / 2, the penumbra being scale (d - z) / z; sun:
// tan(angular radius) / texel, the penumbra being scale (d - z)); base_bias: the hard lookup's bias without its
// slope term; slope: texel (world, at the point) x tan(N, L).
float pcss_fraction(ClientWarpParams params, sampler2D atlas, ClientShadowLight sl, uint face, vec2 position,
                    float distance, float scale, float base_bias, float slope) {
  const bool sun = (sl.flags & kClientShadowSun) != 0u;
  // Blockers between the receiver and the light: a sun's anywhere up to the map's near plane, a cube's from
  // halfway to the light.
  const float search_radius = pcss_radius(sun ? scale * distance : scale);
  const float search_threshold =
      distance - (base_bias + (params.shadow_bias_slope + 1.41421356 * search_radius) * slope);
  float blocker_sum = 0.0;
  uint blockers = 0u;
  for (uint k = 0u; k < kClientPcssSearchGrid * kClientPcssSearchGrid; ++k) {
    const vec2 q = position + vec2(pcss_grid(k % kClientPcssSearchGrid, kClientPcssSearchGrid, search_radius),
                                   pcss_grid(k / kClientPcssSearchGrid, kClientPcssSearchGrid, search_radius));
    const float z = shadow_occluder(atlas, params, sl, face, ivec2(floor(q)));
    if (z < search_threshold) {
      blocker_sum += z;
      ++blockers;
    }
  }
  if (blockers == 0u) return 1.0;
  const float z = blocker_sum / float(blockers);
  const float pcf_radius = pcss_radius(sun ? scale * (distance - z) : scale * (distance - z) / z);
  const float threshold = distance - (base_bias + (params.shadow_bias_slope + 1.41421356 * pcf_radius) * slope);
  uint lit = 0u;
  for (uint k = 0u; k < kClientPcssFilterGrid * kClientPcssFilterGrid; ++k) {
    const vec2 q = position + vec2(pcss_grid(k % kClientPcssFilterGrid, kClientPcssFilterGrid, pcf_radius),
                                   pcss_grid(k / kClientPcssFilterGrid, kClientPcssFilterGrid, pcf_radius));
    if (shadow_occluder(atlas, params, sl, face, ivec2(floor(q))) >= threshold) ++lit;
  }
  return float(lit) / float(kClientPcssFilterGrid * kClientPcssFilterGrid);
}

#endif  // DHR_PCSS_H
