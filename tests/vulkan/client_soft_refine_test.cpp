// Refined soft shares (WarpSettings::soft_refine): the band reconstruction (render/soft_bands.hpp) and the blend at
// a lookup (render/soft_refine.hpp, bilinear_warp.h's warp_soft_blend) on levels whose answer is known, then the
// deferred warp against its CPU reference on the area room with levels that step by one level every few old pixels
// (a smooth share, banded), and the forward pass shading with the same shares as the deferred one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "forward_test_frame.hpp"
#include "render/eye_pipeline.hpp"
#include "render/light_layout.hpp"
#include "render/shadow_maps.hpp"
#include "render/soft_bands.hpp"
#include "render/soft_refine.hpp"
#include "shaders/shader_interface.h"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using namespace forward_test;
using shader::kClientSoftRefineNoneAll;
using shader::kClientSoftRefineScale;

// One soft light (the layout's field 0) and a hard one.
VisibilityLayout one_soft() {
  const bool soft[2] = {true, false};
  return VisibilityLayout::for_lights(std::span<const bool>(soft, 2));
}

constexpr double kTop = kDefaultSoftLevels - 1;  // the top level
constexpr double kByte = 1.0 / kClientSoftRefineScale;
constexpr uint32_t kRadius = 6;  // soft_band_radius of a 300-pixel buffer

// A w x h buffer of one_soft()'s layout: the soft light's share share(x, y) rounded to its level, the hard bit set.
template <typename Share>
VisibilityBuffer soft_buffer(const VisibilityLayout& layout, uint32_t w, uint32_t h, Share share) {
  VisibilityBuffer b = VisibilityBuffer::create(w, h, layout.total_bits());
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      b.set(x, y, layout.with_visibility(layout.with_visibility(0, 1, 1.0f), 0, share(x, y)));
    }
  }
  return b;
}

double share_of(uint32_t packed) { return refined_share(packed, 0); }

// Every pixel's packed band shares (rows that did not arrive: none).
std::vector<uint32_t> band_shares(const VisibilityLayout& layout, const VisibilityBuffer& b,
                                  std::span<const uint8_t> rows, uint32_t bits, uint32_t radius) {
  const SoftBandTable table = soft_band_table(layout, b, rows, bits, radius);
  std::vector<uint32_t> out(b.pixel_count(), kClientSoftRefineNoneAll);
  for (uint32_t y = 0; y < b.height; ++y) {
    if (!rows.empty() && rows[y] == 0) continue;
    for (uint32_t x = 0; x < b.width; ++x) {
      out[size_t{y} * b.width + x] = soft_band_shares_at(table, layout, x, y, b.get(x, y));
    }
  }
  return out;
}

uint32_t soft_bits_of(const VisibilityLayout& layout) { return soft_refine_bits(layout, 0); }

// A share rising linearly across 64 pixels, along x (rows) or y (columns): its levels are bands about 9 pixels wide.
void expect_ramp_reconstructed(bool along_x) {
  const VisibilityLayout layout = one_soft();
  const auto truth = [&](uint32_t x, uint32_t y) { return static_cast<float>(((along_x ? x : y) + 0.5) / 64.0); };
  const VisibilityBuffer b = soft_buffer(layout, along_x ? 64 : 8, along_x ? 8 : 64, truth);
  const std::vector<uint32_t> shares = band_shares(layout, b, {}, soft_bits_of(layout), kRadius);
  double level_error = 0.0, band_error = 0.0, worst = 0.0, last = -1.0;
  for (uint32_t t = 0; t < 64; ++t) {
    const uint32_t x = along_x ? t : 3, y = along_x ? 3 : t;
    const size_t p = size_t{y} * b.width + x;
    const uint32_t mask = b.get(x, y);
    const double share = shaded_share(layout, mask, shares[p], 0), level = layout.visibility(mask, 0);
    const double want = truth(x, y);
    // The bottom and top levels keep theirs (none); the others have a share.
    EXPECT_EQ(share_of(shares[p]) < 0.0, level == 0.0 || level == 1.0) << t;
    EXPECT_LE(std::abs(share - level), 0.5 / kTop + kByte) << t;  // never beyond the interval the level stands for
    EXPECT_GE(share, last - kByte) << t;                          // the ramp rises
    last = share;
    if (t < kRadius || t >= 64 - kRadius) continue;  // the statistics: where the window is not cut by the edge
    level_error += std::abs(level - want);
    band_error += std::abs(share - want);
    worst = std::max(worst, std::abs(share - want));
  }
  std::printf("ramp along %s, away from the edges: mean |level - share| %.5f, reconstructed %.5f (worst %.5f)\n",
              along_x ? "x" : "y", level_error / (64 - 2 * kRadius), band_error / (64 - 2 * kRadius), worst);
  EXPECT_LT(band_error, level_error / 3);  // the bands become the ramp (in steps of a cell, 2 pixels)
  EXPECT_LT(worst, 0.25 / kTop);
}

TEST(SoftBands, ARampOfLevelsIsReconstructedAlongRowsAndColumns) {
  expect_ramp_reconstructed(true);
  expect_ramp_reconstructed(false);
}

TEST(SoftBands, CellsShareTheirWindow) {
  const VisibilityLayout layout = one_soft();
  // Radius 24: cells of 4 x 4 pixels, a window of 13 x 13 cells. A ramp along x over 240 pixels (bands of 34).
  const auto truth = [](uint32_t x, uint32_t) { return (x + 0.5) / 240.0; };
  const VisibilityBuffer b =
      soft_buffer(layout, 240, 40, [&](uint32_t x, uint32_t y) { return static_cast<float>(truth(x, y)); });
  const SoftBandTable table = soft_band_table(layout, b, {}, soft_bits_of(layout), 24);
  ASSERT_EQ(table.cell, 4u);
  ASSERT_EQ(table.columns, 60u);
  ASSERT_EQ(table.rows, 10u);
  ASSERT_EQ(table.words.size(), size_t{60} * 10 * shader::kClientSoftBandCellWords);
  double level_error = 0.0, band_error = 0.0;
  for (uint32_t x = 0; x < 240; ++x) {
    const uint32_t mask = b.get(x, 20);
    const double share = shaded_share(layout, mask, soft_band_shares_at(table, layout, x, 20, mask), 0);
    const double level = layout.visibility(mask, 0);
    EXPECT_LE(std::abs(share - level), 0.5 / kTop + kByte) << x;
    // Pixels of a cell at one level share a byte.
    if (x % 4 != 0 && b.get(x - 1, 20) == mask) {
      EXPECT_EQ(soft_band_shares_at(table, layout, x, 20, mask), soft_band_shares_at(table, layout, x - 1, 20, mask));
    }
    if (x < 30 || x >= 210) continue;
    level_error += std::abs(level - truth(x, 20));
    band_error += std::abs(share - truth(x, 20));
  }
  EXPECT_LT(band_error, level_error / 3);
}

TEST(SoftBands, FlatLevelsAndJumpsKeepTheirLevels) {
  const VisibilityLayout layout = one_soft();
  for (int level = 0; level < 8; ++level) {
    const float k = static_cast<float>(level / kTop);
    const VisibilityBuffer b = soft_buffer(layout, 12, 6, [&](uint32_t, uint32_t) { return k; });
    const std::vector<uint32_t> shares = band_shares(layout, b, {}, soft_bits_of(layout), kRadius);
    for (const uint32_t packed : shares) {
      if (level == 0 || level == 7) {
        EXPECT_EQ(packed, kClientSoftRefineNoneAll) << "level " << level;  // fully hidden or lit: the level holds
      } else {
        EXPECT_NEAR(share_of(packed), level / kTop, kByte) << "level " << level;
      }
      EXPECT_LT(refined_share(packed, 1), 0.0);  // no second soft field
    }
  }
  // Levels 1 and 5 side by side: a contact shadow or another surface, not a penumbra: both keep their levels.
  const VisibilityBuffer jump = soft_buffer(layout, 12, 6, [](uint32_t x, uint32_t) {
    return static_cast<float>((x < 6 ? 1 : 5) / kTop);
  });
  const std::vector<uint32_t> shares = band_shares(layout, jump, {}, soft_bits_of(layout), kRadius);
  for (uint32_t x = 0; x < 12; ++x) EXPECT_NEAR(share_of(shares[2 * 12 + x]), (x < 6 ? 1 : 5) / kTop, kByte) << x;
  // A field outside the bits (an edge light's): none.
  for (const uint32_t packed : band_shares(layout, jump, {}, 0u, kRadius)) EXPECT_EQ(packed, kClientSoftRefineNoneAll);
}

TEST(SoftBands, DitheredLevelsGiveTheirMeanAndMissingRowsCountForNothing) {
  const VisibilityLayout layout = one_soft();
  // Level 4 at a quarter of the pixels (every fourth along a row, shifted each row), 3 elsewhere: the share lies a
  // quarter of the way from 3 to 4. Level 3's pixels show it; level 4's keep the nearest they may (3.5).
  const auto dither = [](uint32_t x, uint32_t y) { return static_cast<float>(((x + y) % 4 == 0 ? 4 : 3) / kTop); };
  const VisibilityBuffer b = soft_buffer(layout, 40, 30, dither);
  std::vector<uint8_t> rows(30, 1);
  rows[12] = 0;
  const std::vector<uint32_t> shares = band_shares(layout, b, rows, soft_bits_of(layout), kRadius);
  for (uint32_t y = 8; y < 22; ++y) {
    for (uint32_t x = 8; x < 32; ++x) {
      const uint32_t packed = shares[size_t{y} * 40 + x];
      if (y == 12) {
        EXPECT_EQ(packed, kClientSoftRefineNoneAll) << x;  // its row did not arrive
        continue;
      }
      // The window holds 13 x 13 pixels less the missing row's: a quarter of them at level 4, within a pixel.
      EXPECT_NEAR(share_of(packed), ((x + y) % 4 == 0 ? 3.5 : 3.25) / kTop, 14.0 / 156.0 / kTop + kByte)
          << x << "," << y;
    }
  }
  // The widest window: its counts fit (radius 100: 13 x 13 cells of 16 x 16 pixels, 208 pixels a side).
  const VisibilityBuffer wide = soft_buffer(layout, 260, 260, dither);
  const std::vector<uint32_t> widest = band_shares(layout, wide, {}, soft_bits_of(layout), kMaxSoftBandRadius);
  EXPECT_NEAR(share_of(widest[size_t{130} * 260 + 131]), 3.25 / kTop, 0.02 / kTop + kByte);
  EXPECT_THROW(soft_band_table(layout, b, std::vector<uint8_t>(4, 1), soft_bits_of(layout), kRadius),
               std::invalid_argument);
  EXPECT_THROW(soft_band_table(layout, b, {}, soft_bits_of(layout), 0), std::invalid_argument);
  EXPECT_THROW(soft_band_table(layout, b, {}, soft_bits_of(layout), kMaxSoftBandRadius + 1), std::invalid_argument);
  // The radius is a share of the width: a 320-pixel eye's buffer with dhr-eval's guard band, the server's 1984.
  EXPECT_EQ(soft_band_radius(340), 7u);
  EXPECT_EQ(soft_band_radius(1984), 40u);
  EXPECT_EQ(soft_band_radius(8), 1u);
  EXPECT_EQ(soft_band_radius(kSoftBandRadiusDivisor * (kMaxSoftBandRadius + 10)), kMaxSoftBandRadius);
}

TEST(SoftBands, NeverLeaveTheIntervalTheLevelStandsFor) {
  const VisibilityLayout layout = one_soft();
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> step(-1, 1);
  // A random walk of levels along each row (steps of one level and jumps), rows shifted against each other.
  std::vector<int> walk(40 * 30);
  for (uint32_t y = 0; y < 30; ++y) {
    int level = static_cast<int>(rng() % 8);
    for (uint32_t x = 0; x < 40; ++x) {
      level = std::clamp(level + (rng() % 7 == 0 ? step(rng) * 3 : step(rng)), 0, 7);
      walk[y * 40 + x] = level;
    }
  }
  const VisibilityBuffer b = soft_buffer(layout, 40, 30, [&](uint32_t x, uint32_t y) {
    return static_cast<float>(walk[y * 40 + x] / kTop);
  });
  const std::vector<uint32_t> shares = band_shares(layout, b, {}, soft_bits_of(layout), kRadius);
  for (size_t p = 0; p < shares.size(); ++p) {
    const double share = shaded_share(layout, b.mask_at(p), shares[p], 0), level = walk[p] / kTop;
    EXPECT_LE(std::abs(share - level), 0.5 / kTop + kByte) << p;
  }
}

TEST(SoftRefine, BlendsTheSamplesBandSharesWithinOneLevel) {
  const VisibilityLayout layout = one_soft();
  const uint32_t bits = soft_bits_of(layout);
  const auto mask = [&](int level) {
    return layout.with_visibility(layout.with_visibility(0, 1, 1.0f), 0, static_cast<float>(level) / 7.0f);
  };
  const auto packed = [](double share) { return 0xFFFFFF00u | static_cast<uint32_t>(std::lround(share * 254)); };
  const std::array<uint32_t, 4> masks{mask(3), mask(4), mask(3), mask(4)};
  const std::array<uint32_t, 4> shares{packed(3.2 / 7), packed(3.7 / 7), packed(3.2 / 7), packed(3.7 / 7)};
  // Halfway in x: the mean of the two columns' shares.
  EXPECT_NEAR(share_of(soft_blend(layout, masks, shares, 0xFu, 0.5, 0.5, mask(3), -1, bits)), 3.45 / 7, 1.5 * kByte);
  // Near the left column: its share.
  EXPECT_NEAR(share_of(soft_blend(layout, masks, shares, 0xFu, 0.0, 0.3, mask(3), -1, bits)), 3.2 / 7, 1.5 * kByte);
  // An exact lookup: its sample's share alone.
  EXPECT_NEAR(share_of(soft_blend(layout, masks, shares, 0xFu, 0.99, 0.0, mask(4), 1, bits)), 3.7 / 7, 1.5 * kByte);
  // Unused samples are left out; a none byte stands for its level.
  EXPECT_NEAR(share_of(soft_blend(layout, masks, shares, 0x5u, 0.5, 0.5, mask(3), -1, bits)), 3.2 / 7, 1.5 * kByte);
  const std::array<uint32_t, 4> none{kClientSoftRefineNoneAll, shares[1], kClientSoftRefineNoneAll, shares[3]};
  EXPECT_NEAR(share_of(soft_blend(layout, masks, none, 0xFu, 0.5, 0.5, mask(3), -1, bits)), 3.35 / 7, 1.5 * kByte);
  // A sample more than a level from the vote's (a contact shadow): left out.
  const std::array<uint32_t, 4> jump{mask(0), mask(4), mask(0), mask(4)};
  EXPECT_NEAR(share_of(soft_blend(layout, jump, shares, 0xFu, 0.4, 0.5, mask(4), -1, bits)), 3.7 / 7, 1.5 * kByte);
  // Outside the refined bits (an edge light's field): none.
  EXPECT_EQ(soft_blend(layout, masks, shares, 0xFu, 0.5, 0.5, mask(3), -1, 0u), kClientSoftRefineNoneAll);
}

TEST(SoftRefine, FieldsFromTheMapsAreDropped) {
  const VisibilityLayout layout = one_soft();
  const uint32_t m = layout.with_visibility(layout.with_visibility(0, 1, 1.0f), 0, 3.0f / 7.0f);
  const uint32_t packed = 0xFFFFFF00u | 100u;
  const uint32_t soft_field = ((1u << layout.bits[0]) - 1u) << layout.offset[0];
  EXPECT_EQ(soft_refine_drop(layout, packed, soft_field), kClientSoftRefineNoneAll);
  EXPECT_EQ(soft_refine_drop(layout, packed, 1u << layout.offset[1]), packed);  // the hard bit: kept
  // shaded_share: the refined share of a soft light, the bit of a hard one, the level without a share.
  EXPECT_NEAR(shaded_share(layout, m, packed, 0), 100.0 / 254.0, 1e-12);
  EXPECT_EQ(shaded_share(layout, m, packed, 1), 1.0);
  EXPECT_NEAR(shaded_share(layout, m, kClientSoftRefineNoneAll, 0), 3.0 / 7.0, 1e-6);
}

using ClientSoftRefineTest = vk::test::VulkanTest;

VisibilityLayout g_layout;  // the area room's, set before the frame is made

// A share that rises slowly across the image, rounded to levels: bands one level apart, several pixels wide.
VisibilityBuffer banded(const Camera& traced, uint32_t) {
  return buffer_of_shares(traced, g_layout, [](uint32_t x, uint32_t y, uint32_t i) {
    const double share = std::fmod((x + 0.6 * y * (i + 1)) / (9.0 * (kDefaultSoftLevels - 1)), 1.0);
    return g_layout.is_soft(i) ? static_cast<float>(share) : 1.0f;
  });
}

TEST_F(ClientSoftRefineTest, WarpsRefineAsTheCpuReferenceDoes) {
  const Scene room = default_room_area();
  g_layout = layout_for_lights(room.lights);  // before the rig makes the frame's bits
  ASSERT_TRUE(g_layout.any_soft());
  SceneRig rig(ctx(), room, banded);
  const ClientScene& gpu_scene = rig.gpu_scene;
  ShadowMaps& maps = rig.maps;
  const ForwardTestFrame& warp = rig.warp;
  const WarpSettings settings = WarpSettings::server_edges();
  ASSERT_TRUE(settings.soft_refine);  // what ships

  EyePipeline deferred(ctx(), gpu_scene, kExtent, deferred_options(settings));
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { deferred.record(cmd, 0, warp.view, warp.input, {}, &maps); });
  const std::vector<uint32_t> gpu_soft = test::read_pixels<uint32_t>(ctx(), deferred.warp().soft);
  const std::vector<uint32_t> gpu_mask = test::read_pixels<uint32_t>(ctx(), deferred.warp().mask);
  const std::vector<uint8_t> deferred_colour = read_rgba8(ctx(), deferred.output());
  const std::vector<glm::vec3> normals = test::read_normal_vectors(ctx(), deferred.gbuffer().normal);

  ForwardFrame frame = warp.frame;
  frame.soft_refine = true;
  const ForwardResult fwd = run_forward(ctx(), gpu_scene, ForwardMode::kServerEdges, frame);
  frame.soft_refine = false;
  const ForwardResult levels_only = run_forward(ctx(), gpu_scene, ForwardMode::kServerEdges, frame);

  WarpInput in = warp.reference_input(fwd.depth);
  in.normals = normals;
  in.settings = settings;
  in.shadow = &rig.shadow;
  const WarpResult cpu = warp_reference(in);
  ASSERT_EQ(gpu_soft.size(), cpu.soft.size());

  size_t compared = 0, refined = 0, between = 0, wrong = 0, colour_far = 0, forward_changed = 0;
  for (size_t i = 0; i < cpu.soft.size(); ++i) {
    if (cpu.margin[i] < kMargin || gpu_mask[i] != cpu.masks[i]) continue;
    ++compared;
    for (uint32_t rank = 0; rank < 4; ++rank) {
      const uint32_t g = (gpu_soft[i] >> (8 * rank)) & 0xFFu, c = (cpu.soft[i] >> (8 * rank)) & 0xFFu;
      // Float sums in another order: a byte may round the other way.
      if ((g == 0xFFu) != (c == 0xFFu) || std::abs(static_cast<int>(g) - static_cast<int>(c)) > 1) {
        if (++wrong <= 5) ADD_FAILURE() << "pixel " << i << " soft field " << rank << ": gpu " << g << ", cpu " << c;
      }
    }
    uint32_t rank = 0;
    for (uint32_t l = 0; l < g_layout.light_count; ++l) {
      if (!g_layout.is_soft(l)) continue;
      const double share = refined_share(cpu.soft[i], rank++);
      if (share < 0.0) continue;
      ++refined;
      const double level = g_layout.visibility(cpu.masks[i], l);
      between += std::abs(share - level) > 1.0 / kClientSoftRefineScale;
    }
    int far = 0;
    for (int c = 0; c < 3; ++c) far = std::max(far, std::abs(fwd.colour[4 * i + c] - deferred_colour[4 * i + c]));
    colour_far += far > 3;
    forward_changed += std::abs(fwd.colour[4 * i] - levels_only.colour[4 * i]) > 0;
  }
  std::printf("soft refine: %zu pixels compared, %zu fields refined (%zu between levels), %zu differ; forward: %zu "
              "colours beyond 3/255 of the deferred path's, %zu changed by the refinement\n",
              compared, refined, between, wrong, colour_far, forward_changed);
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(refined, compared / 2);    // many lookups fall between two levels of a soft field
  EXPECT_GT(between, refined / 10);    // and the bands' edges take shares between the levels
  EXPECT_LE(colour_far, compared / 100);  // the forward pass shades with the same shares
  EXPECT_GT(forward_changed, compared / 20);
}

}  // namespace
}  // namespace dhr::render
