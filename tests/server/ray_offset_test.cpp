// offset_ray_origin: moves toward +n, by an amount that scales with the coordinates, never a fixed epsilon.
#include "ray_offset.hpp"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace dhr::server
