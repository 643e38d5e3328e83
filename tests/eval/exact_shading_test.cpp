// The truth's picture with fractional visibility (bench/eval/exact_shading.hpp): bytes survive the trip through
// radiance unchanged, and a step's weight moves the picture between the two levels' pictures, linearly in radiance.
#include "exact_shading.hpp"

#include "shaders/display_encode.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

using dhr::eval::exposed_radiance;
using dhr::eval::RadianceSum;

uint8_t encode(float radiance) {
  return static_cast<uint8_t>(std::lround(
      dhr::display_encode::srgb_encode(dhr::display_encode::tonemap_aces(radiance)) * 255.0f));
}

TEST(ExactShading, EveryByteIsItsRadiancesEncoding) {
  for (int b = 0; b < 256; ++b) {
    const auto byte = static_cast<uint8_t>(b);
    EXPECT_EQ(encode(exposed_radiance(byte)), byte) << b;
    if (b > 0) {
      EXPECT_GT(exposed_radiance(byte), exposed_radiance(static_cast<uint8_t>(b - 1))) << b;
    }
  }
  EXPECT_EQ(exposed_radiance(0), 0.0f);
}

TEST(ExactShading, StepsAddTheirWeightedRadiance) {
  // Three pixels: no step, half a step, a step with weight 0.25 on a dark and a bright byte.
  const std::vector<uint8_t> base{10, 100, 200, 255, 40, 40, 40, 255, 90, 180, 30, 255};
  const std::vector<uint8_t> stepped{200, 50, 0, 255, 80, 80, 80, 255, 120, 220, 60, 255};
  RadianceSum sum(base);
  const std::vector<float> weight{0.0f, 0.5f, 0.25f};
  sum.add_step(stepped, weight);
  const std::vector<uint8_t> out = sum.encode();
  ASSERT_EQ(out.size(), base.size());
  for (size_t c = 0; c < 4; ++c) EXPECT_EQ(out[c], base[c]) << "weight 0 keeps the base's bytes";
  for (size_t p = 1; p < 3; ++p) {
    for (size_t c = 0; c < 3; ++c) {
      const float want = exposed_radiance(base[p * 4 + c]) +
                         weight[p] * (exposed_radiance(stepped[p * 4 + c]) - exposed_radiance(base[p * 4 + c]));
      EXPECT_EQ(out[p * 4 + c], encode(want)) << p << " " << c;
      EXPECT_GT(out[p * 4 + c], base[p * 4 + c]);
      EXPECT_LT(out[p * 4 + c], stepped[p * 4 + c]);
    }
    EXPECT_EQ(out[p * 4 + 3], 255);
  }
  EXPECT_THROW(sum.add_step(std::vector<uint8_t>(8), weight), std::invalid_argument);
}

}  // namespace
