#include "render/sun_map.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace dhr::render {
namespace {
double boundary_distance(double v) { return std::abs(v - std::round(v)); }
}  // namespace

SunMap fit_sun_map(const SceneBounds& bounds, const glm::dvec3& direction) {
  SunMap sun;
  const glm::dvec3 centre = bounds.empty() ? glm::dvec3(0.0) : glm::dvec3(bounds.center());
  const double r = bounds.empty() ? 1.0 : std::max(0.5 * static_cast<double>(bounds.diagonal()), 1e-3);
  const double half = r + r / 100.0 + 1e-3;
  const glm::dvec3 forward = glm::normalize(direction);
  const glm::dvec3 hint = std::abs(forward.y) < 0.99 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  sun.right = glm::normalize(glm::cross(forward, hint));
  sun.up = glm::cross(sun.right, forward);
  sun.position = centre - forward * half;
  sun.half_extent = half;
  sun.depth_range = 2.0 * half;
  return sun;
}

glm::dmat4 sun_view_projection(const SunMap& sun) {
  const glm::dvec3 back = glm::cross(sun.right, sun.up);
  const double h = sun.half_extent;
  glm::dmat4 m(0.0);
  // Rows: x = right / h, y = -up / h (Vulkan's y-down framebuffer, as the cube faces), depth = 1 + back / range.
  for (int k = 0; k < 3; ++k) {
    m[k][0] = sun.right[k] / h;
    m[k][1] = -sun.up[k] / h;
    m[k][2] = back[k] / sun.depth_range;
  }
  m[3][2] = 1.0;
  m[3][3] = 1.0;
  return m;
}

CubeLookup sun_lookup(const SunMap& sun, const glm::dvec3& v, uint32_t size) {
  CubeLookup c;
  c.face = 0;
  c.distance = glm::dot(v, glm::cross(sun.up, sun.right));
  const double s = size;
  c.position = glm::dvec2((glm::dot(v, sun.right) / sun.half_extent + 1.0) * 0.5 * s,
                          (1.0 - glm::dot(v, sun.up) / sun.half_extent) * 0.5 * s);
  const int last = static_cast<int>(size) - 1;
  c.texel = glm::ivec2(std::clamp(static_cast<int>(std::floor(c.position.x)), 0, last),
                       std::clamp(static_cast<int>(std::floor(c.position.y)), 0, last));
  c.margin = 1e30;
  for (double p : {c.position.x, c.position.y}) {
    if (p > 0.0 && p < s) c.margin = std::min(c.margin, boundary_distance(p));
  }
  return c;
}

}  // namespace dhr::render
