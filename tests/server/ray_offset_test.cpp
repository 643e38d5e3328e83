// offset_ray_origin: moves toward +n, by an amount that scales with the coordinates, never a fixed epsilon.
#include "trace/ray_offset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace dhr::server {
namespace {

TEST(RayOffset, MovesAlongTheNormalOnBothSidesOfZero) {
  for (float base : {0.0f, 0.01f, 1.0f, -1.0f, 37.5f, -4096.0f, 123456.0f}) {
    for (const glm::vec3 n : {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::vec3(0.6f, 0.0f, -0.8f)}) {
      const glm::vec3 p(base, base, base);
      const glm::vec3 o = offset_ray_origin(p, n);
      for (int i = 0; i < 3; ++i) {
        if (n[i] > 0.0f) {
          EXPECT_GT(o[i], p[i]) << base;
        } else if (n[i] < 0.0f) {
          EXPECT_LT(o[i], p[i]) << base;
        } else {
          EXPECT_EQ(o[i], p[i]) << base;
        }
      }
    }
  }
}

TEST(RayOffset, ScalesWithTheMagnitudeOfThePosition) {
  const glm::vec3 n(0, 1, 0);
  const float near_offset = offset_ray_origin(glm::vec3(0, 1.0f, 0), n).y - 1.0f;
  const float far_offset = offset_ray_origin(glm::vec3(0, 1000.0f, 0), n).y - 1000.0f;
  // 256 ULPs: 256 * 2^-23 at 1 m, 256 * 2^-14 at 1000 m.
  EXPECT_FLOAT_EQ(near_offset, 256.0f * std::ldexp(1.0f, -23));
  EXPECT_FLOAT_EQ(far_offset, 256.0f * std::ldexp(1.0f, -14));
  EXPECT_GT(far_offset / near_offset, 500.0f);
  // Near zero: a small absolute offset instead of denormal-sized ULP steps.
  EXPECT_FLOAT_EQ(offset_ray_origin(glm::vec3(0.0f), n).y, kRayOffsetFloatScale);
  EXPECT_GT(offset_ray_origin(glm::vec3(0, -1e-20f, 0), n).y, 1e-6f);
}

TEST(RayOffset, ScaleIsThePowerOfTwoAboveTheSceneSizeOverTheReference) {
  EXPECT_EQ(ray_offset_scale(4.0), 1.0f);  // the chapter's constants up to the reference half-size
  EXPECT_EQ(ray_offset_scale(3.0), 1.0f);
  EXPECT_EQ(ray_offset_scale(2.0), 0.5f);
  EXPECT_EQ(ray_offset_scale(4.5), 2.0f);
  EXPECT_EQ(ray_offset_scale(5e-3), std::ldexp(1.0f, -9));  // 5e-3 / 4 = 1.25e-3 <= 2^-9
  EXPECT_EQ(ray_offset_scale(1e4), 4096.0f);
  // Degenerate sizes keep the chapter's constants; extreme ones stay normal floats.
  EXPECT_EQ(ray_offset_scale(0.0), 1.0f);
  EXPECT_EQ(ray_offset_scale(-1.0), 1.0f);
  EXPECT_EQ(ray_offset_scale(std::numeric_limits<double>::infinity()), 1.0f);
  EXPECT_EQ(ray_offset_scale(1e300), std::ldexp(1.0f, kRayOffsetMaxExponent));
  EXPECT_EQ(ray_offset_scale(1e-300), std::ldexp(1.0f, -kRayOffsetMaxExponent));
  EXPECT_TRUE(std::isnormal(kRayOffsetFloatScale * ray_offset_scale(1e-300)));

  SceneBounds bounds;
  EXPECT_EQ(ray_offset_scale(bounds), 1.0f);  // empty
  bounds.extend(glm::vec3(-1.0f, 0.0f, 100.0f));
  bounds.extend(glm::vec3(1.0f, 3.0f, 116.0f));  // half sides 1, 1.5, 8
  EXPECT_EQ(ray_offset_scale(bounds), 2.0f);
}

TEST(RayOffset, NearOriginTermsScaleExactlyWithTheScene) {
  const glm::vec3 n(0.6f, 0.0f, -0.8f);
  for (const int k : {-12, -3, 0, 5, 14}) {
    const float s = std::ldexp(1.0f, k);
    const RayOffset offset = scaled_ray_offset(s);
    EXPECT_EQ(offset.origin_threshold, kRayOffsetOriginThreshold * s);
    EXPECT_EQ(offset.float_scale, kRayOffsetFloatScale * s);
    EXPECT_FLOAT_EQ(offset_ray_origin(glm::vec3(0.0f), glm::vec3(0, 1, 0), offset).y, kRayOffsetFloatScale * s);
    // A scene scaled by a power of two gets exactly the scaled origins, near zero and far from it.
    for (const glm::vec3 p : {glm::vec3(0.001f, -0.02f, 0.0f), glm::vec3(0.5f, -3.0f, 1.25f), glm::vec3(0.01f, 7.0f, -0.03f)}) {
      const glm::vec3 o = offset_ray_origin(p, n);
      const glm::vec3 scaled = offset_ray_origin(p * s, n, offset);
      for (int i = 0; i < 3; ++i) EXPECT_EQ(scaled[i], o[i] * s) << "k=" << k << " i=" << i;
    }
  }
  // A 5 mm scene: the absolute term shrinks with it (the chapter's 1/65536 would be 0.3 % of its size).
  const RayOffset tiny = scaled_ray_offset(ray_offset_scale(2.5e-3));
  EXPECT_LT(offset_ray_origin(glm::vec3(0.0f), glm::vec3(0, 1, 0), tiny).y, 2.5e-3f * 1e-5f);
}

}  // namespace
}  // namespace dhr::server
