// Robust shadow-ray origins: move a surface point off its surface along the geometric normal by an
// amount that scales with the magnitude of the coordinates (the integer-ULP method described in
// Ray Tracing Gems, chapter 6, "A Fast and Robust Method for Avoiding Self-Intersection").
//
// Far from the origin each coordinate is nudged by a fixed number of units in the last place (ULPs),
// proportional to that normal component: the error of a reconstructed hit point is itself a few ULPs of
// its coordinates, so a constant ULP offset always clears it, at 1 mm or at 1000 km. Near zero, where a
// float's ULP becomes tiny (denormals), a small absolute offset takes over. Never a fixed epsilon.
//
// The chapter's near-zero constants assume coordinates of order one. A hit point near the (re-centred)
// origin is rebuilt from vertices as far out as the scene's size, so its error scales with the scene, and
// a fixed absolute offset is far too large in a 5 mm scene (1.5 % of it) and too small in a 5 km one. Both
// near-zero terms are therefore multiplied by the scene's ray-offset scale: a power of two (exact in float,
// the same on the CPU and the GPU), 1 for scenes up to kRayOffsetReferenceHalfExtent.
#pragma once
#include "scene/scene.hpp"

#include <glm/vec3.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace dhr::server {

// At scale 1: coordinates with |x| below this use the absolute offset (below ~1/32 a ULP is < 4e-9).
inline constexpr float kRayOffsetOriginThreshold = 1.0f / 32.0f;
// At scale 1: absolute offset per unit normal used near the origin.
inline constexpr float kRayOffsetFloatScale = 1.0f / 65536.0f;
// ULPs per unit normal used elsewhere (independent of the scale: ULPs already scale with |x|).
inline constexpr float kRayOffsetIntScale = 256.0f;
// The chapter's constants are used as they are for scenes whose half-size (largest half side of the
// bounding box: the largest |coordinate| in the re-centred frame) is at most this many units.
inline constexpr double kRayOffsetReferenceHalfExtent = 4.0;
// The scale stays within 2^-kRayOffsetMaxExponent .. 2^kRayOffsetMaxExponent (normal floats throughout).
inline constexpr int kRayOffsetMaxExponent = 100;

// The near-origin terms for one scene.
struct RayOffset {
  float origin_threshold = kRayOffsetOriginThreshold;
  float float_scale = kRayOffsetFloatScale;
};

// The smallest power of two >= half_extent / kRayOffsetReferenceHalfExtent (clamped, see above).
inline float ray_offset_scale(double half_extent) {
  if (!(half_extent > 0.0) || !std::isfinite(half_extent)) return 1.0f;
  int exponent = 0;
  const double mantissa = std::frexp(half_extent / kRayOffsetReferenceHalfExtent, &exponent);  // [0.5, 1)
  if (mantissa == 0.5) --exponent;  // already a power of two
  return std::ldexp(1.0f, std::clamp(exponent, -kRayOffsetMaxExponent, kRayOffsetMaxExponent));
}

// The scale for a scene's bounds (1 when empty).
inline float ray_offset_scale(const SceneBounds& bounds) {
  if (bounds.empty()) return 1.0f;
  const glm::dvec3 half = (glm::dvec3(bounds.max) - glm::dvec3(bounds.min)) * 0.5;
  return ray_offset_scale(std::max({half.x, half.y, half.z}));
}

// Both terms times `scale` (a power of two from ray_offset_scale: exact).
inline RayOffset scaled_ray_offset(float scale) {
  return RayOffset{kRayOffsetOriginThreshold * scale, kRayOffsetFloatScale * scale};
}

// p: surface point; n: unit geometric normal pointing to the side the new ray leaves from.
inline glm::vec3 offset_ray_origin(const glm::vec3& p, const glm::vec3& n, const RayOffset& offset = {}) {
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(p[i]) < offset.origin_threshold) {
      out[i] = p[i] + offset.float_scale * n[i];
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
