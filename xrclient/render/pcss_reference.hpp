// CPU reference of the client's PCSS lookup (shaders/client/pcss.h), in double on a read-back atlas: the same taps,
// radii, clamps and biases. shadow_mask_reference (shadow_maps.hpp) calls it for lights with a soft field.
#pragma once
#include <cstdint>
#include <span>

#include "render/shadow_maps.hpp"

namespace dhr::render {

// PCSS's constants (shader_interface.h's kClientPcss*), for reports.
struct PcssTaps {
  uint32_t search = 0;  // blocker-search taps
  uint32_t filter = 0;  // PCF taps
  double min_radius = 0.0;
  double max_radius = 0.0;  // texels
};
PcssTaps pcss_taps();

// The share of a light that a receiver sees, looked up at `c` (its face, continuous texel position and distance
// along the map's axis) in the light's tile. scale: texels per unit of the similar-triangles term (a cube:
// R / d x size / 2 with R the light's radius; a sun: tan(angular radius) / texel size); base_bias: the hard
// lookup's bias without its slope term; slope: a texel's world size at the point x tan(N, L).
double pcss_fraction_reference(const ShadowReference& maps, const ShadowTile& tile, const CubeLookup& c,
                               double scale, double base_bias, double slope);

}  // namespace dhr::render
