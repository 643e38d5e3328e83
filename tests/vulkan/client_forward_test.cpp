// Forward pass (render/forward_pass.hpp) on the project's default room: in the paper-warp mode its masks and
// statuses equal the CPU warp reference on every pixel not within kMargin of a flip (the reference run on the
// forward pass's own depth, which equals the G-buffer pass's bit for bit), its counts equal its status image,
// and its colours equal the deferred pipeline's (G-buffer -> warp -> shading) within 2/255 wherever their
// masks agree; the Lambert mode lights every surface pixel; the shadow-map mode agrees with the compute warp's
// shadow lookups (`local`); the server-edges mode (WarpSettings::server_edges) equals the CPU reference and the
// deferred pipeline wherever it takes no shadow-map bit, and nearly everywhere else; bad input is rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "client_test_helpers.hpp"
#include "forward_test_frame.hpp"
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/forward_pass.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/offscreen_sink.hpp"
#include "render/shadow_maps.hpp"
#include "render/warp_pass.hpp"
#include "render/warp_reference.hpp"
#include "scene/scene.hpp"
#include "vk/image.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

namespace fs = std::filesystem;
using ClientForwardTest = vk::test::VulkanTest;

using namespace forward_test;

TEST_F(ClientForwardTest, PaperWarpEqualsTheCpuReferenceAndTheDeferredPipeline) {
  const Scene scene = default_room();
  const ClientScene gpu_scene(ctx(), scene);
  const ForwardTestFrame warp(scene, patterned);
  const VisibilityInput& input = warp.input;
  const View& view = warp.view;
  const ForwardFrame& frame = warp.frame;
  const ForwardResult fwd = run_forward(ctx(), gpu_scene, ForwardMode::kPaperWarp, frame);

  // The forward depth is the G-buffer pass's, bit for bit.
  GBuffer gbuffer = GBuffer::create(ctx(), kExtent);
  GBufferPass gpass(ctx(), gpu_scene);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { gpass.record(cmd, gbuffer, frame.display, kNear); });
  const std::vector<float> gdepth = test::read_pixels<float>(ctx(), gbuffer.depth);
  ASSERT_EQ(gdepth.size(), fwd.depth.size());
  size_t depth_differs = 0;
  for (size_t i = 0; i < gdepth.size(); ++i) depth_differs += gdepth[i] != fwd.depth[i] ? 1 : 0;
  EXPECT_EQ(depth_differs, 0u);

  const WarpResult cpu = warp_reference(warp.reference_input(fwd.depth));
  size_t compared = 0, ambiguous = 0, mismatches = 0;
  std::array<uint64_t, kWarpStatusCount> from_image{};
  for (size_t i = 0; i < fwd.depth.size(); ++i) {
    if (fwd.status[i] < kWarpStatusCount) ++from_image[fwd.status[i]];
    if (cpu.margin[i] < kMargin) {
      ++ambiguous;
      continue;
    }
    ++compared;
    const bool background = cpu.status[i] == WarpStatus::kBackground;
    if (fwd.status[i] != static_cast<uint32_t>(cpu.status[i]) || (!background && fwd.mask[i] != cpu.masks[i])) {
      if (++mismatches <= 5) {
        ADD_FAILURE() << "pixel " << i % kExtent.width << "," << i / kExtent.width << ": forward mask " << fwd.mask[i]
                      << " status " << fwd.status[i] << ", cpu mask " << cpu.masks[i] << " status "
                      << to_string(cpu.status[i]);
      }
    }
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_LT(ambiguous, fwd.depth.size() / 50) << "too many ambiguous pixels for a meaningful test";
  for (size_t s = 0; s < kWarpStatusCount; ++s) EXPECT_EQ(fwd.counts.by_status[s], from_image[s]) << s;
  // The test means something: known, outside and missing-row pixels all occur; every pixel is counted once.
  EXPECT_GT(fwd.counts[WarpStatus::kKnown], kExtent.width * kExtent.height / 2);
  EXPECT_GT(fwd.counts[WarpStatus::kOutside], 0u);
  EXPECT_GT(fwd.counts[WarpStatus::kMissingRow], 0u);
  EXPECT_EQ(fwd.counts.surface() + fwd.counts[WarpStatus::kBackground], uint64_t{kExtent.width} * kExtent.height);

  // The deferred pipeline with the same inputs: the same colours within 2/255 wherever the masks agree.
  EyePipelineOptions deferred_options;
  deferred_options.forward = false;
  EyePipeline eye(ctx(), gpu_scene, kExtent, deferred_options);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { eye.record(cmd, 0, view, input); });
  ASSERT_FALSE(eye.read_stats(0).forward);
  const std::vector<uint8_t> deferred = read_rgba8(ctx(), eye.output());
  const std::vector<uint32_t> deferred_mask = test::read_pixels<uint32_t>(ctx(), eye.warp().mask);
  size_t same_mask = 0, off = 0;
  int worst = 0;
  for (size_t i = 0; i < fwd.depth.size(); ++i) {
    if (fwd.depth[i] > 0.0f && deferred_mask[i] != fwd.mask[i]) continue;
    ++same_mask;
    for (int c = 0; c < 3; ++c) {
      const int diff = std::abs(int{deferred[i * 4 + c]} - int{fwd.colour[i * 4 + c]});
      worst = std::max(worst, diff);
      if (diff > 2) ++off;
    }
  }
  EXPECT_GT(same_mask, fwd.depth.size() * 95 / 100);
  EXPECT_EQ(off, 0u) << "largest channel difference " << worst;
}

TEST_F(ClientForwardTest, LambertLightsEverythingAndShadowMapsAgreeWithTheComputeLookup) {
  const Scene scene = default_room();
  const ClientScene gpu_scene(ctx(), scene);
  const ShadowMaps maps(ctx(), gpu_scene);
  const View view = traced_view();
  ForwardFrame frame;
  frame.display = display_camera(view, kExtent);
  frame.near_plane = kNear;
  frame.lights = scene.lights;
  frame.shadow_maps = &maps;
  const ForwardResult lambert = run_forward(ctx(), gpu_scene, ForwardMode::kLambert, frame);
  const ForwardResult shadowed = run_forward(ctx(), gpu_scene, ForwardMode::kShadowMaps, frame);
  EXPECT_EQ(lambert.counts.surface() + lambert.counts[WarpStatus::kBackground], 0u);  // only the paper warp counts

  // The compute warp's `local`: no visibility, every pixel from the shadow maps.
  EyePipelineOptions options;
  options.warp.shadow_fill = true;
  EyePipeline eye(ctx(), gpu_scene, kExtent, options);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { eye.record(cmd, 0, view, VisibilityInput{}, {}, &maps); });
  const std::vector<uint32_t> local = test::read_pixels<uint32_t>(ctx(), eye.warp().mask);
  const uint32_t all = (1u << scene.lights.size()) - 1u;
  size_t surface = 0, agree = 0, shadowed_bits = 0;
  for (size_t i = 0; i < lambert.depth.size(); ++i) {
    if (!(lambert.depth[i] > 0.0f)) continue;
    ++surface;
    EXPECT_EQ(lambert.mask[i], 0xFFFFFFFFu);
    EXPECT_EQ(lambert.status[i], static_cast<uint32_t>(WarpStatus::kKnown));
    agree += (shadowed.mask[i] & all) == (local[i] & all) ? 1 : 0;
    shadowed_bits += (shadowed.mask[i] & all) != all ? 1 : 0;
  }
  ASSERT_GT(surface, kExtent.width * kExtent.height / 2);
  EXPECT_GT(shadowed_bits, surface / 20) << "the view has shadows";
  // The compute path reads half-float normals from the G-buffer, the forward pass the interpolated ones: a
  // bit within a hair of its bias may differ.
  EXPECT_GE(static_cast<double>(agree), 0.995 * static_cast<double>(surface));
  // Shadows darken: no channel brighter than Lambert's.
  for (size_t i = 0; i < lambert.colour.size(); ++i) ASSERT_LE(shadowed.colour[i], lambert.colour[i]) << i;
}

TEST_F(ClientForwardTest, ServerEdgesEqualsTheCpuReferenceAndTheDeferredPipeline) {
  const Scene scene = default_room();
  const ClientScene gpu_scene(ctx(), scene);
  const ShadowMaps maps(ctx(), gpu_scene);
  const ForwardTestFrame warp(scene, blocky, &maps);  // lost rows: from the shadow maps
  const VisibilityInput& input = warp.input;
  const View& view = warp.view;
  std::vector<uint64_t> edges_at;  // shadow-map edge pixels per band
  // Without the edge band and with the shipped one (which widens the edges to most of this blocky buffer).
  for (const uint32_t band : {0u, client::shipped::kEdgeBand}) {
    SCOPED_TRACE("edge band " + std::to_string(band));
    ForwardFrame frame = warp.frame;
    frame.edge_band = band;
    const ForwardResult fwd = run_forward(ctx(), gpu_scene, ForwardMode::kServerEdges, frame);

    // The deferred pipeline with the same settings: its G-buffer normals feed the CPU reference.
    EyePipeline deferred(ctx(), gpu_scene, kExtent, deferred_options(WarpSettings::server_edges(band)));
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { deferred.record(cmd, 0, view, input, {}, &maps); });
    ASSERT_FALSE(deferred.read_stats(0).forward);
    const std::vector<uint32_t> deferred_mask = test::read_pixels<uint32_t>(ctx(), deferred.warp().mask);
    const std::vector<glm::vec3> normals = test::read_normal_vectors(ctx(), deferred.gbuffer().normal);
    std::vector<float> atlas_storage;
    const ShadowReference shadow = shadow_reference(ctx(), maps, atlas_storage);

    WarpInput in = warp.reference_input(fwd.depth);
    in.normals = normals;
    in.settings = WarpSettings::server_edges(band);
    in.shadow = &shadow;
    const WarpResult cpu = warp_reference(in);

    // Where the forward pass took no shadow-map bit, its mask is the server's: equal to the CPU reference and
    // the deferred pipeline on every pixel. Where it took some, the normals differ (interpolated floats here,
    // the G-buffer's half floats there): a bit within a hair of its bias may differ.
    size_t compared = 0, ambiguous = 0, mismatches = 0, from_shadow = 0, shadow_differs = 0, deferred_differs = 0;
    std::array<uint64_t, kWarpStatusCount> from_image{};
    uint64_t fills = 0, edges = 0;
    for (size_t i = 0; i < fwd.depth.size(); ++i) {
      const uint32_t status = fwd.status[i] & shader::kClientForwardStatusMask;
      if (status < kWarpStatusCount) ++from_image[status];
      const bool filled = (fwd.status[i] & shader::kClientForwardStatusShadowFill) != 0;
      const bool edge = (fwd.status[i] & shader::kClientForwardStatusShadowEdge) != 0;
      fills += filled ? 1 : 0;
      edges += edge ? 1 : 0;
      if (cpu.margin[i] < kMargin) {
        ++ambiguous;
        continue;
      }
      ++compared;
      const bool background = cpu.status[i] == WarpStatus::kBackground;
      if (status != static_cast<uint32_t>(cpu.status[i]) || filled != (cpu.fill[i] == WarpFill::kShadowMap)) {
        if (++mismatches <= 5) {
          ADD_FAILURE() << "pixel " << i % kExtent.width << "," << i / kExtent.width << ": forward status "
                        << fwd.status[i] << ", cpu status " << to_string(cpu.status[i]) << " fill "
                        << static_cast<int>(cpu.fill[i]);
        }
        continue;
      }
      if (background) continue;
      if (filled || edge) {
        ++from_shadow;
        shadow_differs += fwd.mask[i] != cpu.masks[i] ? 1 : 0;
        deferred_differs += fwd.mask[i] != deferred_mask[i] ? 1 : 0;
      } else if (fwd.mask[i] != cpu.masks[i] || fwd.mask[i] != deferred_mask[i]) {
        if (++mismatches <= 5) {
          ADD_FAILURE() << "pixel " << i % kExtent.width << "," << i / kExtent.width << ": forward mask " << fwd.mask[i]
                        << ", cpu mask " << cpu.masks[i] << ", deferred mask " << deferred_mask[i];
        }
      }
    }
    EXPECT_EQ(mismatches, 0u);
    // More than the paper's warp: the margin also covers the vote's ties and the shadow maps' bias and texels.
    EXPECT_LT(ambiguous, fwd.depth.size() / 10) << "too many ambiguous pixels for a meaningful test";
    EXPECT_LE(shadow_differs, from_shadow / 200) << "of " << from_shadow;
    EXPECT_LE(deferred_differs, from_shadow / 200) << "of " << from_shadow;

    std::printf("server edges: %zu pixels compared, %zu ambiguous; %zu took shadow-map bits (%llu edges, %llu fills), "
                "%zu differ from the CPU reference, %zu from the deferred pipeline\n",
                compared, ambiguous, from_shadow, static_cast<unsigned long long>(edges),
                static_cast<unsigned long long>(fills), shadow_differs, deferred_differs);

    // Counts: as the status image says, and as the CPU reference's (ambiguous pixels aside).
    for (size_t s = 0; s < kWarpStatusCount; ++s) EXPECT_EQ(fwd.counts.by_status[s], from_image[s]) << s;
    EXPECT_EQ(fwd.counts.filled_shadow_map, fills);
    EXPECT_EQ(fwd.counts.edges_shadow_map, edges);
    const auto near = [&](uint64_t a, uint64_t b) { return (a > b ? a - b : b - a) <= ambiguous; };
    EXPECT_TRUE(near(fwd.counts.filled_shadow_map, cpu.counts.filled_shadow_map))
        << fwd.counts.filled_shadow_map << " vs " << cpu.counts.filled_shadow_map;
    EXPECT_TRUE(near(fwd.counts.edges_shadow_map, cpu.counts.edges_shadow_map))
        << fwd.counts.edges_shadow_map << " vs " << cpu.counts.edges_shadow_map;
    // The test means something: known, outside and missing-row pixels, shadow edges and fills all occur, and
    // the shadow maps are looked up at a minority of the pixels.
    EXPECT_GT(fwd.counts[WarpStatus::kKnown], kExtent.width * kExtent.height / 2);
    EXPECT_GT(fwd.counts[WarpStatus::kOutside], 0u);
    EXPECT_GT(fwd.counts[WarpStatus::kMissingRow], 0u);
    EXPECT_GT(edges, 0u);
    EXPECT_EQ(fills, fwd.counts.unknown_surface());
    if (band == 0) {
      EXPECT_LT(edges + fills, fwd.counts.surface() / 2);
    }
    edges_at.push_back(edges);
    EXPECT_EQ(fwd.counts.surface() + fwd.counts[WarpStatus::kBackground], uint64_t{kExtent.width} * kExtent.height);

    // The eye pipeline takes the forward path for these settings, with the shadow maps bound: the same masks.
    EyePipelineOptions forward_options;
    forward_options.forward_mask = true;
    forward_options.warp = WarpSettings::server_edges(band);
    EyePipeline eye(ctx(), gpu_scene, kExtent, forward_options);
    ASSERT_TRUE(eye.uses_forward());
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { eye.record(cmd, 0, view, input, {}, &maps); });
    const EyeStats stats = eye.read_stats(0);
    EXPECT_TRUE(stats.forward);
    EXPECT_EQ(stats.warp, fwd.counts);
    EXPECT_EQ(test::read_pixels<uint32_t>(ctx(), eye.mask()), fwd.mask);
    // And switches back to the paper's warp with the same pipeline.
    eye.warp_settings() = WarpSettings{};
    ASSERT_TRUE(eye.uses_forward());
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { eye.record(cmd, 0, view, input, {}, &maps); });
    EXPECT_EQ(eye.read_stats(0).warp.edges_shadow_map + eye.read_stats(0).warp.filled_shadow_map, 0u);
  }
  EXPECT_GT(edges_at[1], edges_at[0]) << "the band widens the edges";
}

TEST_F(ClientForwardTest, BadInputIsRejected) {
  const Scene scene = default_room();
  const ClientScene gpu_scene(ctx(), scene);
  ForwardPass paper(ctx(), gpu_scene);
  ForwardTargets targets = ForwardTargets::create(ctx(), kExtent, {});
  ForwardFrame frame;
  frame.display = display_camera(traced_view(), Extent{kExtent.width + 1, kExtent.height});
  frame.lights = scene.lights;
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    EXPECT_THROW(paper.record(cmd, 0, frame, targets), std::invalid_argument);  // size
    frame.display = display_camera(traced_view(), kExtent);
    EXPECT_THROW(paper.record(cmd, 1, frame, targets), std::invalid_argument);  // slot
    frame.shading.view = ShadingView::kAlbedo;
    EXPECT_THROW(paper.record(cmd, 0, frame, targets), std::invalid_argument);  // debug view
  });
  ForwardOptions shadow_options;
  shadow_options.mode = ForwardMode::kShadowMaps;
  ForwardPass shadow(ctx(), gpu_scene, shadow_options);
  ForwardTargets shadow_targets = ForwardTargets::create(ctx(), kExtent, shadow_options);
  frame.shading.view = ShadingView::kShaded;
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    EXPECT_THROW(shadow.record(cmd, 0, frame, shadow_targets), std::invalid_argument);  // no maps
  });
  ForwardOptions edges_options;
  edges_options.mode = ForwardMode::kServerEdges;
  ForwardPass edges(ctx(), gpu_scene, edges_options);
  ForwardTargets edges_targets = ForwardTargets::create(ctx(), kExtent, edges_options);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    EXPECT_THROW(edges.record(cmd, 0, frame, edges_targets), std::invalid_argument);  // no maps
  });
  EXPECT_THROW(edges.set_mode(ForwardMode::kShadowMaps), std::invalid_argument);  // other attachments
  EXPECT_NO_THROW(edges.set_mode(ForwardMode::kPaperWarp));
  // A paper-warp pass with an unusable visibility input treats it as none: every surface pixel is unknown.
  VisibilityBuffer wrong = VisibilityBuffer::create(3, 3, static_cast<uint32_t>(scene.lights.size()));
  VisibilityInput input;
  input.buffer = &wrong;
  input.traced = Camera::with_guard_band(traced_view(), kExtent, kGuard);
  frame.visibility = &input;
  ForwardPass::Recorded recorded;
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { recorded = paper.record(cmd, 0, frame, targets); });
  EXPECT_FALSE(recorded.visibility_used);
  const WarpCounts counts = paper.read_counts(0);
  EXPECT_EQ(counts[WarpStatus::kKnown], 0u);
  EXPECT_GT(counts[WarpStatus::kNoData], 0u);
}

}  // namespace
}  // namespace dhr::render
