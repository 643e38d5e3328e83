// The warp's motion rule on the real client passes (issue 27, DESIGN 5b): a still head over a floor, an occluder that
// moves between the scene time the visibility was traced for (0 s) and the one displayed (1 s). The paper's warp
// keeps the old shadow (it trusts every traced bit); the shipped warp (edges: forward and deferred) and the full warp
// take the bits motion may have changed from the shadow maps, re-rendered at the displayed time, and agree with the
// exact visibility at 1 s (Embree moved there) but for the shadow maps' own edge pixels. Visibility traced for the
// displayed time itself has nothing unknown.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "client_test_helpers.hpp"
#include "frame/stereo_pipeline.hpp"
#include "moving_scene.hpp"
#include "render/client_motion.hpp"
#include "render/client_scene.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/light_layout.hpp"
#include "render/render_camera.hpp"
#include "render/warp_motion.hpp"
#include "render/warp_reference.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "vk/image.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using ClientWarpFullMotionTest = vk::test::VulkanTest;

constexpr Extent kExtent{96, 72};

constexpr int64_t kTracedAt = 0;
constexpr int64_t kShownAt = 1'000'000'000;  // the occluder moved 1 m along +x and turned 30 degrees

VisibilityBuffer trace_at(server::EmbreeTracer& tracer, const Camera& camera, double t) {
  tracer.set_scene_time(t);
  VisibilityBuffer out;
  server::TraceStats stats;
  tracer.trace(camera, out, stats);
  return out;
}

struct Shown {
  std::vector<uint32_t> mask;
  EyeStats stats;
};

// Eye 0 of a still stereo pair showing kShownAt with the visibility traced at kTracedAt (for the display camera
// itself: the warp is the identity, so only motion can make a bit wrong).
Shown show(vk::Context& ctx, const ClientScene& gpu, const WarpSettings& warp, bool forward,
           const VisibilityInput& input) {
  EyePipelineOptions options;
  options.frames_in_flight = 1;
  options.warp = warp;
  options.forward = forward;
  options.forward_mask = true;
  client::StereoPipeline stereo(ctx, gpu, kExtent, options);
  client::StereoInputs inputs;
  inputs.views = {camera_view(), camera_view()};
  inputs.visibility = {input, input};
  inputs.scene_time_ns = kShownAt;
  ctx.submit_and_wait([&](VkCommandBuffer cmd) { stereo.record(cmd, 0, inputs); });
  Shown out;
  out.stats = stereo.read_stats(0)[0];
  out.mask.resize(size_t{kExtent.width} * kExtent.height);
  vk::read_image(ctx, stereo.eye(0).mask(), out.mask.data(), out.mask.size() * sizeof(uint32_t));
  return out;
}

// The G-buffer depth of the frame shown (the scene at kShownAt): surface pixels are those > 0.
std::vector<float> shown_depth(vk::Context& ctx, const ClientScene& gpu) {
  MovedScene moved;
  gpu.motion().sample(scene_seconds(kShownAt), gpu.meshes(), moved);
  const GBufferPass pass(ctx, gpu);
  GBuffer targets = GBuffer::create(ctx, kExtent);
  const Camera camera = display_camera(camera_view(), kExtent);
  ctx.submit_and_wait([&](VkCommandBuffer cmd) { pass.record(cmd, targets, camera, kDefaultNearPlane, &moved); });
  return test::read_pixels<float>(ctx, targets.depth);
}

// Pixels whose light-A bit (bit 0) differs between `mask` and `exact`, over surface pixels of `exact`'s camera.
uint32_t wrong_a(const std::vector<uint32_t>& mask, const VisibilityBuffer& exact, const std::vector<float>& depth) {
  uint32_t wrong = 0;
  for (size_t i = 0; i < mask.size(); ++i) {
    if (depth[i] > 0.0f && ((mask[i] ^ exact.mask_at(i)) & 1u) != 0u) ++wrong;
  }
  return wrong;
}

TEST_F(ClientWarpFullMotionTest, ThePaperWarpKeepsTheOldShadowTheShippedWarpDoesNot) {
  const Scene scene = moving_scene();
  const ClientScene gpu(ctx(), scene);
  server::EmbreeTracer tracer(scene, server::TracerOptions{});
  const Camera camera = display_camera(camera_view(), kExtent);
  const VisibilityBuffer old_bits = trace_at(tracer, camera, 0.0);
  const VisibilityBuffer exact = trace_at(tracer, camera, 1.0);
  VisibilityInput input;
  input.buffer = &old_bits;
  input.traced = camera;
  input.scene_time_ns = kTracedAt;
  const std::vector<float> depth = shown_depth(ctx(), gpu);
  const Shown paper = show(ctx(), gpu, WarpSettings{}, false, input);
  uint32_t moved_shadow = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    if (depth[i] > 0.0f && ((old_bits.mask_at(i) ^ exact.mask_at(i)) & 1u) != 0u) ++moved_shadow;
  }
  ASSERT_GT(moved_shadow, 40u) << "the occluder's shadow must move on screen";
  EXPECT_EQ(wrong_a(paper.mask, exact, depth), moved_shadow) << "the paper's warp shows the traced (old) bits";
  EXPECT_EQ(paper.stats.warp.motion_unknown, 0u);

  struct Case {
    const char* name;
    WarpSettings warp;
    bool forward;
  };
  for (const Case& c : {Case{"edges forward (shipped)", WarpSettings::server_edges(), true},
                        Case{"edges deferred", WarpSettings::server_edges(), false},
                        Case{"full", WarpSettings::full(), false}}) {
    SCOPED_TRACE(c.name);
    const Shown shown = show(ctx(), gpu, c.warp, c.forward, input);
    const uint32_t wrong = wrong_a(shown.mask, exact, depth);
    EXPECT_LE(wrong, moved_shadow / 10) << "the moved shadow comes from the re-rendered shadow maps";
    EXPECT_GT(shown.stats.warp.motion_unknown, 0u);
    // Without the rule the same warp keeps the old shadow.
    WarpSettings still = c.warp;
    still.motion = false;
    const Shown kept = show(ctx(), gpu, still, c.forward, input);
    EXPECT_GE(wrong_a(kept.mask, exact, depth), moved_shadow * 8 / 10);
    EXPECT_EQ(kept.stats.warp.motion_unknown, 0u);
  }
}

TEST_F(ClientWarpFullMotionTest, NothingIsUnknownWhenTheTracedTimeIsTheShownOne) {
  const Scene scene = moving_scene();
  const ClientScene gpu(ctx(), scene);
  server::EmbreeTracer tracer(scene, server::TracerOptions{});
  const Camera camera = display_camera(camera_view(), kExtent);
  const VisibilityBuffer exact = trace_at(tracer, camera, 1.0);
  VisibilityInput input;
  input.buffer = &exact;
  input.traced = camera;
  input.scene_time_ns = kShownAt;
  const Shown shown = show(ctx(), gpu, WarpSettings::server_edges(), true, input);
  EXPECT_EQ(shown.stats.warp.motion_unknown, 0u);
  EXPECT_EQ(wrong_a(shown.mask, exact, shown_depth(ctx(), gpu)), 0u);
}

}  // namespace
}  // namespace dhr::render
