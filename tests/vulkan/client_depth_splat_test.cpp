// The traced depth made from a display frame's depth (WarpSettings::depth_splat, render/traced_depth_splat.hpp):
// the GPU splat equals its CPU reference; it shows the surfaces the traced camera's own raster shows, on most
// texels; an eye pipeline with the setting has no traced depth before its first frame (no test then), splats its
// previous frame's depth from the second on, and its warp then equals the CPU reference warp over that depth, on
// the deferred and the forward path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "forward_test_frame.hpp"
#include "render/eye_pipeline.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/shadow_maps.hpp"
#include "render/traced_depth_splat.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using ClientDepthSplatTest = vk::test::VulkanTest;
using namespace forward_test;

// Texels where two splats differ: one holds a surface the other does not, or their depths differ by more than
// float rounding of the same point (the GPU computes in float, the reference in double).
size_t differing_texels(const std::vector<float>& a, const std::vector<float>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const bool differ = (a[i] > 0.0f) != (b[i] > 0.0f) || std::abs(a[i] - b[i]) > 1e-5f * std::max(a[i], b[i]);
    n += differ ? 1 : 0;
  }
  return n;
}

TEST_F(ClientDepthSplatTest, EqualsTheCpuReferenceAndShowsTheTracedSurfaces) {
  const Scene scene = default_room();
  const ClientScene gpu_scene(ctx(), scene);
  const GBufferPass gbuffer_pass(ctx(), gpu_scene);
  const Camera display = display_camera(display_view(), kExtent);
  GBuffer shown = GBuffer::create(ctx(), kExtent);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { gbuffer_pass.record(cmd, shown, display, kNear); });
  const std::vector<float> display_depth = test::read_pixels<float>(ctx(), shown.depth);
  TracedDepthSplat splat(ctx(), 1, 1);

  for (const uint32_t scale : {1u, 2u}) {
    SCOPED_TRACE("depth scale " + std::to_string(scale));
    const Camera traced = depth_camera(Camera::with_guard_band(traced_view(), kExtent, kGuard), scale);
    GBuffer target = GBuffer::create(ctx(), traced.extent);
    ctx().submit_and_wait(
        [&](VkCommandBuffer cmd) { splat.record(cmd, 0, 0, shown.depth, display, target.depth, traced, kNear); });
    const std::vector<float> gpu = test::read_pixels<float>(ctx(), target.depth);
    const std::vector<float> cpu = splat_traced_depth_reference(display_depth, display, traced, kNear);
    ASSERT_EQ(gpu.size(), cpu.size());
    // A point within float rounding of a texel border may land on either side.
    EXPECT_LE(differing_texels(gpu, cpu), gpu.size() / 500);

    // Against the traced camera's own raster: where both hold a surface, it is the same one (within the depth
    // test's plane tolerance along the texel's ray), and the splat holds a surface on most of the raster's texels.
    GBuffer rastered = GBuffer::create(ctx(), traced.extent);
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { gbuffer_pass.record(cmd, rastered, traced, kNear); });
    const std::vector<float> truth = test::read_pixels<float>(ctx(), rastered.depth);
    size_t surfaces = 0, covered = 0, agree = 0;
    for (size_t i = 0; i < truth.size(); ++i) {
      if (!(truth[i] > 0.0f)) continue;
      ++surfaces;
      if (!(gpu[i] > 0.0f)) continue;
      ++covered;
      const double z_truth = kNear / double{truth[i]}, z_splat = kNear / double{gpu[i]};
      agree += std::abs(z_splat - z_truth) <= 0.02 * z_truth + 0.01 ? 1 : 0;
    }
    std::printf("depth scale %u: %zu surface texels, %zu splatted, %zu of them the same surface\n", scale, surfaces,
                covered, agree);
    EXPECT_GE(covered, surfaces * 8 / 10);
    EXPECT_GE(agree, covered * 97 / 100);
  }
  // Sizes that differ from the cameras' are refused.
  GBuffer wrong = GBuffer::create(ctx(), Extent{8, 8});
  EXPECT_THROW(ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    splat.record(cmd, 0, 0, shown.depth, display, wrong.depth, display, kNear);
  }),
               std::invalid_argument);
  EXPECT_THROW(splat_traced_depth_reference(std::vector<float>(3, 0.5f), display, display, kNear),
               std::invalid_argument);
}

TEST_F(ClientDepthSplatTest, EyePipelineSplatsItsPreviousFrameAndWarpsAsTheReference) {
  const DefaultRoomRig rig(ctx());
  const ClientScene& gpu_scene = rig.gpu_scene;
  const ShadowMaps& maps = rig.maps;
  const ShadowReference& shadow = rig.shadow;
  const ForwardTestFrame& warp = rig.warp;
  WarpSettings settings = WarpSettings::server_edges_depth(1);
  settings.depth_splat = true;
  ASSERT_TRUE(settings.is_server_edges());

  EyePipeline deferred(ctx(), gpu_scene, kExtent, deferred_options(settings));
  EyePipelineOptions forward_options;
  forward_options.forward_mask = true;
  forward_options.warp = settings;
  EyePipeline forward(ctx(), gpu_scene, kExtent, forward_options);
  ASSERT_TRUE(forward.uses_forward());
  const auto run = [&](EyePipeline& eye) {
    ctx().submit_and_wait([&](VkCommandBuffer cmd) {
      eye.prepare(cmd, 0, warp.input);
      eye.record(cmd, 0, warp.view, warp.input, {}, &maps);
    });
    return eye.read_stats(0);
  };
  // The first frame has no previous one: no traced depth, no test.
  for (EyePipeline* eye : {&deferred, &forward}) {
    EXPECT_FALSE(run(*eye).traced_depth_rendered);
    EXPECT_EQ(eye->traced_depth(warp.traced), nullptr);
  }
  const std::vector<float> first_depth = test::read_pixels<float>(ctx(), deferred.gbuffer().depth);

  // The second frame splats the first one's depth (the same display view) into the traced camera.
  const EyeStats deferred_stats = run(deferred);
  ASSERT_TRUE(deferred_stats.traced_depth_rendered);
  vk::Image* splatted = deferred.traced_depth(warp.traced);
  ASSERT_NE(splatted, nullptr);
  const std::vector<float> traced_depth = test::read_pixels<float>(ctx(), *splatted);
  EXPECT_LE(differing_texels(traced_depth,
                             splat_traced_depth_reference(first_depth, warp.frame.display, warp.traced, kNear)),
            traced_depth.size() / 500);

  const std::vector<uint32_t> deferred_mask = test::read_pixels<uint32_t>(ctx(), deferred.warp().mask);
  const std::vector<uint32_t> deferred_status = test::read_pixels<uint32_t>(ctx(), deferred.warp().status);
  const std::vector<float> display_depth = test::read_pixels<float>(ctx(), deferred.gbuffer().depth);
  EXPECT_EQ(display_depth, first_depth);  // the same view twice
  WarpInput in = warp.reference_input(display_depth);
  const std::vector<glm::vec3> normals = test::read_normal_vectors(ctx(), deferred.gbuffer().normal);
  in.normals = normals;  // a span: the vector must outlive the reference's run
  in.sources[0].traced_depth = traced_depth;
  in.settings = settings;
  in.shadow = &shadow;
  const WarpResult cpu = warp_reference(in);
  size_t compared = 0, wrong = 0;
  for (size_t i = 0; i < display_depth.size(); ++i) {
    if (cpu.margin[i] < kMargin) continue;
    ++compared;
    const bool ok = (deferred_status[i] & 0xFFu) == static_cast<uint32_t>(cpu.status[i]) &&
                    deferred_mask[i] == cpu.masks[i];
    if (!ok && ++wrong <= 5) {
      ADD_FAILURE() << "pixel " << i % kExtent.width << "," << i / kExtent.width << ": deferred status "
                    << deferred_status[i] << " mask " << deferred_mask[i] << ", cpu " << to_string(cpu.status[i])
                    << " mask " << cpu.masks[i];
    }
  }
  std::printf("splatted depth: %zu compared, %llu disoccluded, %zu differ\n", compared,
              static_cast<unsigned long long>(cpu.counts[WarpStatus::kDisoccluded]), wrong);
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(compared, display_depth.size() * 9 / 10);
  // The test means something: samples the traced camera saw on another surface are not used.
  EXPECT_GT(cpu.counts[WarpStatus::kDisoccluded], 0u);

  // The forward path splats its own previous frame's depth (the same view): the same traced depth, and its masks
  // equal the deferred ones but for plane tests within a hair of their tolerance (interpolated normals).
  const EyeStats forward_stats = run(forward);
  ASSERT_TRUE(forward_stats.forward);
  ASSERT_TRUE(forward_stats.traced_depth_rendered);
  EXPECT_EQ(test::read_pixels<float>(ctx(), *forward.traced_depth(warp.traced)), traced_depth);
  const std::vector<uint32_t> forward_mask = test::read_pixels<uint32_t>(ctx(), forward.mask());
  size_t forward_wrong = 0;
  for (size_t i = 0; i < forward_mask.size(); ++i) forward_wrong += forward_mask[i] != deferred_mask[i] ? 1 : 0;
  EXPECT_LE(forward_wrong, forward_mask.size() / 200);

  // A new size starts over: no previous frame.
  forward.resize(Extent{kExtent.width, kExtent.height + 2});
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { forward.prepare(cmd, 0, warp.input); });
  EXPECT_FALSE(forward.read_stats(0).traced_depth_rendered);
}

}  // namespace
}  // namespace dhr::render
