// The client's skip: the prediction pass skips the visibility upload when a slot already holds the same
// key (VisibilityInput::key). Rendering a frame sequence with keys must give the same image bytes as
// uploading every frame (key 0), whatever the slot order.
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/offscreen_sink.hpp"
#include "client_test_helpers.hpp"
#include "stress_support.hpp"
#include "test_scenes.hpp"
#include "vulkan_test_fixture.hpp"

#include <gtest/gtest.h>

namespace dhr::stress {
namespace {

using ClientSkipEquivalence = vk::test::VulkanTest;

TEST_F(ClientSkipEquivalence, VisibilityUploadKeyChangesNoByte) {
  const std::string path = test::source_path(kDefaultScenePath);
  const Scene room = load_scene_or_fail(path);
  const Extent extent{48, 36};
  View view;
  view.pose = render::test::look_at({0.0, 1.6, 1.35}, {-0.1, 0.5, -0.9});
  view.fov = Fov{-0.742f, 0.742f, 0.779f, -0.779f};
  const Camera traced = Camera::with_guard_band(view, extent, GuardBand{4, 3});
  // Two different buffers: the traced one, and the same with the first light switched off.
  const VisibilityBuffer a = trace_once(server::TracerBackend::kEmbree, room, traced);
  VisibilityBuffer b = a;
  for (size_t i = 0; i < b.pixel_count(); ++i) b.set_mask_at(i, b.mask_at(i) & ~1u);
  ASSERT_FALSE(a == b);
  // Frame sequence: buffer, key, slot (2 slots): repeats, switches, and a key seen in the other slot.
  struct FrameIn {
    const VisibilityBuffer* buffer;
    uint64_t key;
    uint32_t slot;
  };
  const std::vector<FrameIn> frames = {{&a, 1, 0}, {&a, 1, 1}, {&a, 1, 0}, {&b, 2, 1},
                                       {&b, 2, 0}, {&a, 1, 1}, {&a, 1, 0}, {&b, 2, 0}};
  const render::ClientScene gpu_scene(ctx(), room);
  render::EyePipelineOptions options;
  options.frames_in_flight = 2;
  render::EyePipeline keyed(ctx(), gpu_scene, extent, options), plain(ctx(), gpu_scene, extent, options);
  uint64_t differing = 0;
  for (const FrameIn& f : frames) {
    VisibilityInput input;
    input.buffer = f.buffer;
    input.traced = traced;
    input.key = f.key;
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { keyed.record(cmd, f.slot, view, input); });
    const std::vector<uint8_t> with_skip = render::read_rgba8(ctx(), keyed.output());
    input.key = 0;
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { plain.record(cmd, f.slot, view, input); });
    const std::vector<uint8_t> without = render::read_rgba8(ctx(), plain.output());
    for (size_t i = 0; i < with_skip.size(); ++i) differing += with_skip[i] != without[i];
  }
  report("skip_client_upload_key", "differing_bytes", double(differing), 0.0);
  EXPECT_EQ(differing, 0u);
}

}  // namespace
}  // namespace dhr::stress
