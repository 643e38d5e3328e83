// Refined soft shares (WarpSettings::soft_refine; render/soft_refine.hpp, bilinear_warp.h's warp_soft_refine): the
// function on windows whose answer is known, then the deferred warp against its CPU reference on the area room
// with levels that step by one level every few old pixels (a smooth share, banded), and the forward pass shading
// with the same shares as the deferred one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "forward_test_frame.hpp"
#include "render/eye_pipeline.hpp"
#include "render/light_layout.hpp"
#include "render/shadow_maps.hpp"
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

// A window whose columns 0-1 hold level `left` and columns 2-3 level `right` (the hard bit set everywhere).
SoftWindow columns(const VisibilityLayout& layout, float left, float right) {
  SoftWindow w;
  for (int j = 0; j < 16; ++j) {
    uint32_t m = layout.with_visibility(0, 1, 1.0f);
    m = layout.with_visibility(m, 0, (j % 4) < 2 ? left : right);
    w.masks[static_cast<size_t>(j)] = m;
    w.present |= 1u << j;
  }
  return w;
}

double share_of(uint32_t packed) { return refined_share(packed, 0); }

TEST(SoftRefine, FlatLevelsKeepTheirLevel) {
  const VisibilityLayout layout = one_soft();
  for (int level = 0; level < 8; ++level) {
    const float k = static_cast<float>(level) / 7.0f;
    const SoftWindow w = columns(layout, k, k);
    // One level over the window: nothing to refine, the level holds.
    const uint32_t packed = soft_refine(layout, w, 0.3, 0.7, w.masks[5]);
    EXPECT_EQ(packed, kClientSoftRefineNoneAll) << "level " << level;
    EXPECT_EQ(shaded_share(layout, w.masks[5], packed, 0), static_cast<double>(k));
  }
  // A step in the window: the fields get their bytes; a second soft field would get the next byte, none here.
  const SoftWindow step = columns(layout, 0.0f, 1.0f / 7.0f);
  EXPECT_GE(refined_share(soft_refine(layout, step, 0.5, 0.5, step.masks[5]), 0), 0.0);
  EXPECT_LT(refined_share(soft_refine(layout, step, 0.5, 0.5, step.masks[5]), 1), 0.0);
  // The soft light an edge light (a sun's): never refined.
  EXPECT_EQ(soft_refine(layout, step, 0.5, 0.5, step.masks[5], 1u), kClientSoftRefineNoneAll);
}

TEST(SoftRefine, AStepOfOneLevelBecomesARamp) {
  const VisibilityLayout layout = one_soft();
  const float lo = 3.0f / 7.0f, hi = 4.0f / 7.0f;
  const double lo_d = lo, hi_d = hi;
  const SoftWindow w = columns(layout, lo, hi);
  double last = -1.0;
  for (int i = 0; i <= 10; ++i) {
    const double fx = i / 10.0 * 0.999;
    const uint32_t value = layout.with_visibility(w.masks[5], 0, fx < 0.5 ? lo : hi);  // the vote's level
    const double share = share_of(soft_refine(layout, w, fx, 0.5, value));
    EXPECT_GT(share, lo_d) << fx;
    EXPECT_LT(share, hi_d) << fx;
    EXPECT_GE(share, last - 1e-9) << fx;  // the ramp rises as the lookup moves toward the higher level
    last = share;
  }
  // Halfway between the two columns' centres (fx 0.5 past column 1's centre): the mean of the two levels.
  EXPECT_NEAR(share_of(soft_refine(layout, w, 0.5, 0.5, w.masks[6])), (lo_d + hi_d) / 2.0,
              1.0 / kClientSoftRefineScale);
}

TEST(SoftRefine, AJumpOfMoreThanOneLevelIsKept) {
  const VisibilityLayout layout = one_soft();
  const SoftWindow w = columns(layout, 0.0f, 5.0f / 7.0f);
  // The vote says level 5: the level-0 pixels are another surface's or a contact shadow's, not mixed in.
  EXPECT_NEAR(share_of(soft_refine(layout, w, 0.9, 0.5, w.masks[6])), 5.0 / 7.0, 0.5 / kClientSoftRefineScale);
  EXPECT_NEAR(share_of(soft_refine(layout, w, 0.1, 0.5, w.masks[5])), 0.0, 0.5 / kClientSoftRefineScale);
}

TEST(SoftRefine, MissingPixelsAreLeftOutAndFieldsFromTheMapsDropped) {
  const VisibilityLayout layout = one_soft();
  SoftWindow w = columns(layout, 2.0f / 7.0f, 3.0f / 7.0f);
  w.present = 0x3333u;  // only columns 0-1: one level, which holds
  EXPECT_EQ(soft_refine(layout, w, 0.5, 0.5, w.masks[5]), kClientSoftRefineNoneAll);
  w.present = 0x7777u;  // columns 0-2: a third of the tent's weight at the higher level at fx = 0.5 ...
  const double share = share_of(soft_refine(layout, w, 0.5, 0.5, w.masks[5]));
  EXPECT_NEAR(share, (2.0 * (0.5 + 1.5) + 3.0 * 1.5) / 3.5 / 7.0, 1.0 / kClientSoftRefineScale);
  const uint32_t packed = soft_refine(layout, columns(layout, 3.0f / 7.0f, 4.0f / 7.0f), 0.5, 0.5, w.masks[5]);
  const uint32_t soft_field = ((1u << layout.bits[0]) - 1u) << layout.offset[0];
  EXPECT_EQ(soft_refine_drop(layout, packed, soft_field), kClientSoftRefineNoneAll);
  EXPECT_EQ(soft_refine_drop(layout, packed, 1u << layout.offset[1]), packed);  // the hard bit: kept
  // shaded_share: the refined share of a soft light, the bit of a hard one.
  EXPECT_NEAR(shaded_share(layout, w.masks[5], packed, 0), share_of(packed), 1e-12);
  EXPECT_EQ(shaded_share(layout, w.masks[5], packed, 1), 1.0);
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
