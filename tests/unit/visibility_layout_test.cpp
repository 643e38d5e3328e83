// VisibilityLayout: one bit per hard light, kSoftLevelBits Gray-coded levels per soft light, in the lights'
// order; soft lights that would overflow 32 bits take one bit (counted); fields round-trip every level.
#include <gtest/gtest.h>

#include <array>

#include "visibility/visibility_layout.hpp"

namespace dhr {
namespace {

TEST(VisibilityLayout, HardLightsTakeOneBitEach) {
  const std::array<bool, 3> soft{false, false, false};
  const VisibilityLayout layout = VisibilityLayout::for_lights(soft);
  EXPECT_EQ(layout, VisibilityLayout::hard(3));
  EXPECT_EQ(layout.total_bits(), 3u);
  EXPECT_EQ(layout.used_bits(), 7u);
  EXPECT_FALSE(layout.any_soft());
  EXPECT_EQ(layout.mask_width(), MaskWidth::k8);
  for (uint32_t i = 0; i < 3; ++i) EXPECT_EQ(layout.offset[i], i);
  EXPECT_EQ(layout.visibility(0b101u, 0), 1.0f);
  EXPECT_EQ(layout.visibility(0b101u, 1), 0.0f);
  EXPECT_EQ(layout.with_visibility(0b101u, 1, 0.7f), 0b111u);
  EXPECT_EQ(layout.with_visibility(0b101u, 2, 0.2f), 0b001u);
  EXPECT_EQ(VisibilityLayout::hard(0).total_bits(), 0u);
}

TEST(VisibilityLayout, SoftLightsHoldEveryLevelInGrayCode) {
  const std::array<bool, 3> soft{false, true, false};
  const VisibilityLayout layout = VisibilityLayout::for_lights(soft);
  EXPECT_EQ(layout.offset[0], 0u);
  EXPECT_EQ(layout.offset[1], 1u);
  EXPECT_EQ(layout.bits[1], kSoftLevelBits);
  EXPECT_EQ(layout.offset[2], 1u + kSoftLevelBits);
  EXPECT_EQ(layout.total_bits(), 2u + kSoftLevelBits);
  EXPECT_TRUE(layout.any_soft());
  for (uint32_t level = 0; level < kDefaultSoftLevels; ++level) {
    const float k = dequantize(level, kDefaultSoftLevels);
    const uint32_t mask = layout.with_visibility(0b10001u, 1, k);  // the hard lights' bits stay
    EXPECT_EQ(mask & 1u, 1u);
    EXPECT_EQ(mask >> layout.offset[2], 1u);
    EXPECT_EQ(layout.field(mask, 1), gray_encode(level));
    EXPECT_EQ(layout.visibility(mask, 1), k);
  }
  EXPECT_EQ(layout.visibility(layout.with_visibility(0, 1, 0.0f), 1), 0.0f);
  EXPECT_EQ(layout.visibility(layout.with_visibility(0, 1, 1.0f), 1), 1.0f);
  const uint32_t lit = layout.all_lit();
  for (uint32_t i = 0; i < 3; ++i) EXPECT_EQ(layout.visibility(lit, i), 1.0f) << i;
  EXPECT_EQ(lit & ~layout.used_bits(), 0u);
  EXPECT_EQ(VisibilityLayout::hard(3).all_lit(), 7u);
}

TEST(VisibilityLayout, SoftLightsThatDoNotFitTakeOneBit) {
  // 12 soft lights: 10 fit with 3 bits while every later light keeps its bit (10 * 3 + 2 = 32).
  std::array<bool, 12> soft{};
  soft.fill(true);
  const VisibilityLayout layout = VisibilityLayout::for_lights(soft);
  EXPECT_EQ(layout.total_bits(), 32u);
  EXPECT_EQ(layout.demoted, 2u);
  EXPECT_EQ(layout.used_bits(), 0xFFFFFFFFu);
  EXPECT_EQ(layout.mask_width(), MaskWidth::k32);
  for (uint32_t i = 0; i < 10; ++i) EXPECT_TRUE(layout.is_soft(i)) << i;
  EXPECT_FALSE(layout.is_soft(10));
  EXPECT_FALSE(layout.is_soft(11));
  std::array<bool, 33> too_many{};
  EXPECT_THROW(VisibilityLayout::for_lights(too_many), std::invalid_argument);
  EXPECT_THROW(VisibilityLayout::hard(33), std::invalid_argument);
}

}  // namespace
}  // namespace dhr
