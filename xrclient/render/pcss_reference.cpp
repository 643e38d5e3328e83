#include "render/pcss_reference.hpp"

#include <algorithm>
#include <cmath>

#include "shaders/shader_interface.h"

namespace dhr::render {
namespace {

using shader::kClientPcssFilterGrid;
using shader::kClientPcssMaxRadius;
using shader::kClientPcssMinRadius;
using shader::kClientPcssSearchGrid;

double grid(uint32_t k, uint32_t g, double radius) { return radius * ((2.0 * k + 1.0) / g - 1.0); }

double clamp_radius(double r) {
  return std::clamp(r, static_cast<double>(kClientPcssMinRadius), static_cast<double>(kClientPcssMaxRadius));
}

}  // namespace

PcssTaps pcss_taps() {
  return PcssTaps{kClientPcssSearchGrid * kClientPcssSearchGrid, kClientPcssFilterGrid * kClientPcssFilterGrid,
                  kClientPcssMinRadius, kClientPcssMaxRadius};
}

double pcss_fraction_reference(const ShadowReference& maps, const ShadowTile& tile, const CubeLookup& c,
                               double scale, double base_bias, double slope) {
  const uint32_t row = *tile.row;
  const uint32_t size = maps.face_size;
  const size_t atlas_width = size_t{6} * size;
  const int last = static_cast<int>(size) - 1;
  auto occluder = [&](double x, double y) {
    const int tx = std::clamp(static_cast<int>(std::floor(x)), 0, last);
    const int ty = std::clamp(static_cast<int>(std::floor(y)), 0, last);
    const size_t index = (size_t{row} * size + static_cast<size_t>(ty)) * atlas_width + size_t{c.face} * size +
                         static_cast<size_t>(tx);
    const double stored = maps.atlas[index];
    if (!(stored > 0.0)) return 3.0e38;
    return tile.sun ? (1.0 - stored) * tile.sun->depth_range : maps.settings.near_plane / stored;
  };
  const double d = c.distance;
  const double slope_bias = maps.settings.bias_slope;
  const bool sun = tile.sun.has_value();
  // Blockers between the receiver and the light: a sun's anywhere up to the map's near plane, a cube's from
  // halfway to the light.
  const double search = clamp_radius(sun ? scale * d : scale);
  const double search_threshold = d - (base_bias + (slope_bias + std::sqrt(2.0) * search) * slope);
  double blocker_sum = 0.0;
  uint32_t blockers = 0;
  for (uint32_t k = 0; k < kClientPcssSearchGrid * kClientPcssSearchGrid; ++k) {
    const double z = occluder(c.position.x + grid(k % kClientPcssSearchGrid, kClientPcssSearchGrid, search),
                              c.position.y + grid(k / kClientPcssSearchGrid, kClientPcssSearchGrid, search));
    if (z < search_threshold) {
      blocker_sum += z;
      ++blockers;
    }
  }
  if (blockers == 0) return 1.0;
  const double z = blocker_sum / blockers;
  const double filter = clamp_radius(sun ? scale * (d - z) : scale * (d - z) / z);
  const double threshold = d - (base_bias + (slope_bias + std::sqrt(2.0) * filter) * slope);
  uint32_t lit = 0;
  for (uint32_t k = 0; k < kClientPcssFilterGrid * kClientPcssFilterGrid; ++k) {
    const double x = c.position.x + grid(k % kClientPcssFilterGrid, kClientPcssFilterGrid, filter);
    const double y = c.position.y + grid(k / kClientPcssFilterGrid, kClientPcssFilterGrid, filter);
    if (occluder(x, y) >= threshold) ++lit;
  }
  return static_cast<double>(lit) / (kClientPcssFilterGrid * kClientPcssFilterGrid);
}

}  // namespace dhr::render
