// Robust shadow-ray origins: move a surface point off its surface along the geometric normal by an
// amount that scales with the magnitude of the coordinates (the integer-ULP method described in
// Ray Tracing Gems, chapter 6, "A Fast and Robust Method for Avoiding Self-Intersection").
//
// Far from the origin each coordinate is nudged by a fixed number of units in the last place (ULPs),
// proportional to that normal component: the error of a reconstructed hit point is itself a few ULPs of
// its coordinates, so a constant ULP offset always clears it, at 1 mm or at 1000 km. Near zero, where a
// float's ULP becomes tiny (denormals), a small absolute offset takes over. Never a fixed epsilon.
#pragma once
#include <glm/vec3.hpp>

#include <bit>
#include <cmath>
#include <cstdint>

namespace dhr::server {

// Coordinates with |x| below this use the absolute offset (below ~1/32 a ULP is < 4e-9).
inline constexpr float kRayOffsetOriginThreshold = 1.0f / 32.0f;
// Absolute offset per unit normal used near the origin.
inline constexpr float kRayOffsetFloatScale = 1.0f / 65536.0f;
// ULPs per unit normal used elsewhere.
inline constexpr float kRayOffsetIntScale = 256.0f;

// p: surface point; n: unit geometric normal pointing to the side the new ray leaves from.
inline glm::vec3 offset_ray_origin(const glm::vec3& p, const glm::vec3& n) {
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(p[i]) < kRayOffsetOriginThreshold) {
      out[i] = p[i] + kRayOffsetFloatScale * n[i];
      continue;
    }
    // Moving the bit pattern by k moves the float by k ULPs, away from zero for the sign of p, so add
    // the offset with the sign that moves the value toward +n.
    const int32_t ulps = static_cast<int32_t>(kRayOffsetIntScale * n[i]);
    const int32_t bits = std::bit_cast<int32_t>(p[i]);
    out[i] = std::bit_cast<float>(p[i] < 0.0f ? bits - ulps : bits + ulps);
  }
  return out;
}

}  // namespace dhr::server
