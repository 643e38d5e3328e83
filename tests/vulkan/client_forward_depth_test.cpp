// The server-edges warp with the depth test (WarpSettings::server_edges_depth) against a traced depth at full,
// half and quarter resolution (depth_camera): the deferred pipeline (G-buffer normals) equals the CPU reference
// on every pixel not within kMargin of a flip; the forward pass (interpolated float normals, so a plane test
// within a hair of its tolerance may go the other way) equals it on all but a few pixels; the eye pipeline
// renders the traced depth at the scale itself and takes the forward path with the same masks.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <vector>

#include "forward_test_frame.hpp"
#include "render/eye_pipeline.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/shadow_maps.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using ClientForwardDepthTest = vk::test::VulkanTest;
using namespace forward_test;

TEST_F(ClientForwardDepthTest, EqualsTheCpuReferenceAtEveryDepthScale) {
  const DefaultRoomRig rig(ctx());
  const ClientScene& gpu_scene = rig.gpu_scene;
  const ShadowMaps& maps = rig.maps;
  const ShadowReference& shadow = rig.shadow;
  const ForwardTestFrame& warp = rig.warp;
  const GBufferPass gbuffer_pass(ctx(), gpu_scene);

  for (const uint32_t scale : {1u, 2u, 4u}) {
    SCOPED_TRACE("depth scale " + std::to_string(scale));
    const WarpSettings settings = WarpSettings::server_edges_depth(scale);
    ASSERT_TRUE(settings.is_server_edges());
    // The traced depth at the scale, as the eye pipeline's prepare() renders it.
    const Camera depth_cam = depth_camera(warp.traced, scale);
    ASSERT_EQ(depth_cam.extent.width, (warp.traced.extent.width + scale - 1) / scale);
    GBuffer traced = GBuffer::create(ctx(), depth_cam.extent);
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { gbuffer_pass.record(cmd, traced, depth_cam, kNear); });
    const std::vector<float> traced_depth = test::read_pixels<float>(ctx(), traced.depth);

    ForwardFrame frame = warp.frame;
    frame.traced_depth = &traced.depth;
    frame.depth_test = settings;
    frame.edge_band = settings.edge_band;
    const ForwardResult fwd = run_forward(ctx(), gpu_scene, ForwardMode::kServerEdges, frame);

    // The deferred pipeline with the same settings renders its own traced depth in prepare().
    EyePipeline deferred(ctx(), gpu_scene, kExtent, deferred_options(settings));
    ctx().submit_and_wait([&](VkCommandBuffer cmd) {
      deferred.prepare(cmd, 0, warp.input);
      deferred.record(cmd, 0, warp.view, warp.input, {}, &maps);
    });
    ASSERT_FALSE(deferred.read_stats(0).forward);
    ASSERT_TRUE(deferred.read_stats(0).traced_depth_rendered);
    EXPECT_EQ(test::read_pixels<float>(ctx(), *deferred.traced_depth(warp.traced)), traced_depth);
    const std::vector<uint32_t> deferred_mask = test::read_pixels<uint32_t>(ctx(), deferred.warp().mask);
    const std::vector<uint32_t> deferred_status = test::read_pixels<uint32_t>(ctx(), deferred.warp().status);
    const std::vector<glm::vec3> normals = test::read_normal_vectors(ctx(), deferred.gbuffer().normal);

    WarpInput in = warp.reference_input(fwd.depth);
    in.normals = normals;
    in.sources[0].traced_depth = traced_depth;
    in.settings = settings;
    in.shadow = &shadow;
    const WarpResult cpu = warp_reference(in);

    size_t compared = 0, ambiguous = 0, deferred_wrong = 0, forward_wrong = 0;
    for (size_t i = 0; i < fwd.depth.size(); ++i) {
      if (cpu.margin[i] < kMargin) {
        ++ambiguous;
        continue;
      }
      ++compared;
      const uint32_t cpu_status = static_cast<uint32_t>(cpu.status[i]);
      const bool deferred_ok = (deferred_status[i] & 0xFFu) == cpu_status && deferred_mask[i] == cpu.masks[i];
      if (!deferred_ok && ++deferred_wrong <= 5) {
        ADD_FAILURE() << "pixel " << i % kExtent.width << "," << i / kExtent.width << ": deferred status "
                      << deferred_status[i] << " mask " << deferred_mask[i] << ", cpu " << to_string(cpu.status[i])
                      << " mask " << cpu.masks[i];
      }
      const uint32_t forward_status = fwd.status[i] & shader::kClientForwardStatusMask;
      forward_wrong += forward_status != cpu_status || fwd.mask[i] != cpu.masks[i] ? 1 : 0;
    }
    std::printf("depth scale %u: %zu compared, %zu ambiguous, %llu disoccluded; %zu differ deferred, %zu forward\n",
                scale, compared, ambiguous, static_cast<unsigned long long>(cpu.counts[WarpStatus::kDisoccluded]),
                deferred_wrong, forward_wrong);
    EXPECT_EQ(deferred_wrong, 0u);
    EXPECT_LE(forward_wrong, compared / 500);
    EXPECT_LT(ambiguous, fwd.depth.size() / 10);
    // The test means something: the display moved, and surfaces it sees were hidden from the traced eye.
    EXPECT_GT(cpu.counts[WarpStatus::kDisoccluded], 0u);
    EXPECT_EQ(fwd.counts.filled_shadow_map, fwd.counts.unknown_surface());

    // The eye pipeline: prepare() renders the same depth, record() takes the forward path: the forward masks.
    EyePipelineOptions forward_options;
    forward_options.forward_mask = true;
    forward_options.warp = settings;
    EyePipeline eye(ctx(), gpu_scene, kExtent, forward_options);
    ASSERT_TRUE(eye.uses_forward());
    ctx().submit_and_wait([&](VkCommandBuffer cmd) {
      eye.prepare(cmd, 0, warp.input);
      eye.record(cmd, 0, warp.view, warp.input, {}, &maps);
    });
    const EyeStats stats = eye.read_stats(0);
    EXPECT_TRUE(stats.forward);
    EXPECT_TRUE(stats.traced_depth_rendered);
    EXPECT_EQ(stats.warp, fwd.counts);
    EXPECT_EQ(test::read_pixels<uint32_t>(ctx(), eye.mask()), fwd.mask);
  }
}

TEST_F(ClientForwardDepthTest, DepthCameraCoversWholeTexels) {
  const Camera traced = Camera::with_guard_band(traced_view(), Extent{161, 121}, kGuard);
  EXPECT_TRUE(depth_camera(traced, 1).extent == traced.extent);
  const Camera half = depth_camera(traced, 2);
  EXPECT_EQ(half.extent.width, (traced.extent.width + 1) / 2);
  EXPECT_EQ(half.extent.height, (traced.extent.height + 1) / 2);
  // Texel t's centre is old pixel coordinate (t + 0.5) * 2: the same ray.
  const glm::dvec3 a = half.eye_ray(3.5, 7.5);
  const glm::dvec3 b = traced.eye_ray(7.0, 15.0);
  EXPECT_NEAR(a.x, b.x, 1e-12);
  EXPECT_NEAR(a.y, b.y, 1e-12);
  EXPECT_THROW(depth_camera(traced, 0), std::invalid_argument);
  EXPECT_THROW(depth_camera(traced, 17), std::invalid_argument);
}

}  // namespace
}  // namespace dhr::render
