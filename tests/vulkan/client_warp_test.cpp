// Warp pass: the GPU result equals the CPU reference (warp_reference) exactly, for camera
// translations, rotations, FOV changes, points behind the old eye, lookups outside the old buffer, missing
// rows and every mask width; the identity warp returns the traced masks; far from the origin it is unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "client_test_helpers.hpp"
#include "metrics/visibility_synthetic.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/warp_pass.hpp"
#include "render/render_camera.hpp"
#include "render/warp_reference.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using ClientWarpTest = vk::test::VulkanTest;

constexpr Extent kExtent{96, 72};
constexpr GuardBand kGuard{4, 3};
constexpr double kNear = kDefaultNearPlane;
// Decisions closer than this to flipping (pixels) are removed from the test inputs (see warp_reference.hpp).
constexpr double kMargin = 2e-3;

// A depth field with structure: a slanted wall 2-6 m away, a box 0.4-0.9 m in front of the eye (behind an
// old eye that moved forward), and a background corner.
std::vector<float> synthetic_depth() {
  std::vector<float> depth(size_t{kExtent.width} * kExtent.height);
  for (uint32_t j = 0; j < kExtent.height; ++j) {
    for (uint32_t i = 0; i < kExtent.width; ++i) {
      double z = 2.0 + 4.0 * i / kExtent.width + 0.3 * std::sin(j * 0.37);
      if (i > 30 && i < 50 && j > 20 && j < 40) z = 0.4 + 0.5 * j / kExtent.height;
      const bool background = i + j < 12;
      depth[size_t{j} * kExtent.width + i] = background ? 0.0f : static_cast<float>(kNear / z);
    }
  }
  return depth;
}

View base_view() {
  View view;
  view.pose = test::look_at({0.3, 1.6, 2.0}, {0.0, 1.2, -3.0});
  view.fov = Fov{-0.70f, 0.62f, 0.58f, -0.66f};  // asymmetric, like a headset's eye
  return view;
}

// The paper's warp of one source (the WarpFrame the old record() signature described).
bool record_warp(VkCommandBuffer cmd, WarpPass& pass, vk::Image& depth, const Camera& display,
                 const VisibilityInput& input, WarpTargets& targets) {
  WarpFrame frame;
  frame.depth = &depth;
  frame.display = display;
  frame.near_plane = kNear;
  frame.sources[0].visibility = &input;
  return pass.record(cmd, 0, frame, targets);
}

struct GpuWarp {
  std::vector<uint32_t> masks;
  std::vector<uint32_t> status;
  WarpCounts counts;
};

class WarpRig {
 public:
  // Status and motion vectors on by default: the tests compare statuses with the CPU reference.
  explicit WarpRig(vk::Context& ctx, WarpOutputs outputs = {true, true})
      : ctx_(ctx), pass_(ctx), targets_(WarpTargets::create(ctx, kExtent, outputs)) {
    depth_ = GBuffer::create(ctx, kExtent).depth;
  }

  GpuWarp run(const std::vector<float>& depth, const Camera& display, const VisibilityInput& input) {
    vk::upload_image(ctx_, depth_, depth.data(), depth.size() * sizeof(float));
    ctx_.submit_and_wait([&](VkCommandBuffer cmd) { record_warp(cmd, pass_, depth_, display, input, targets_); });
    GpuWarp out;
    out.masks = test::read_pixels<uint32_t>(ctx_, targets_.mask);
    if (targets_.has_status()) out.status = test::read_pixels<uint32_t>(ctx_, targets_.status);
    out.counts = pass_.read_counts(0);
    return out;
  }

 private:
  vk::Context& ctx_;
  WarpPass pass_;
  WarpTargets targets_;
  vk::Image depth_;
};

WarpResult reference(const std::vector<float>& depth, const Camera& display, const VisibilityInput& input) {
  WarpInput in;
  in.depth = depth;
  in.display = display;
  in.sources[0].traced = input.traced;
  in.near_plane = kNear;
  in.sources[0].visibility = input.buffer;
  in.sources[0].row_valid = input.row_valid;
  return warp_reference(in);
}

// Makes pixels whose decision is within kMargin of flipping background; returns how many.
size_t remove_ambiguous(std::vector<float>& depth, const WarpResult& ref) {
  size_t removed = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    if (ref.margin[i] < kMargin) {
      depth[i] = 0.0f;
      ++removed;
    }
  }
  return removed;
}

// Runs CPU and GPU on the same (sanitized) inputs and requires identical masks, statuses and counts.
WarpResult expect_gpu_equals_cpu(WarpRig& rig, const Camera& display, const VisibilityInput& input) {
  std::vector<float> depth = synthetic_depth();
  const size_t removed = remove_ambiguous(depth, reference(depth, display, input));
  EXPECT_LT(removed, depth.size() / 50) << "too many ambiguous pixels for a meaningful test";
  const WarpResult cpu = reference(depth, display, input);
  const GpuWarp gpu = rig.run(depth, display, input);
  size_t mismatches = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    if (gpu.masks[i] != cpu.masks[i] || gpu.status[i] != static_cast<uint32_t>(cpu.status[i])) {
      if (++mismatches <= 5) {
        ADD_FAILURE() << "pixel " << i % kExtent.width << "," << i / kExtent.width << ": gpu mask " << gpu.masks[i]
                      << " status " << gpu.status[i] << ", cpu mask " << cpu.masks[i] << " status "
                      << to_string(cpu.status[i]) << " lookup " << cpu.lookup[i].x << "," << cpu.lookup[i].y;
      }
    }
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(gpu.counts, cpu.counts);
  return cpu;
}

struct Move {
  const char* name;
  View old_view;
  Extent old_display = kExtent;
};

TEST_F(ClientWarpTest, GpuMatchesCpuReferenceForCameraMoves) {
  const View now = base_view();
  const Camera display = display_camera(now, kExtent);
  auto translated = [&](glm::dvec3 d) {
    View v = now;
    v.pose.position += d;
    return v;
  };
  View wider = now;
  wider.fov = Fov{-0.78f, 0.70f, 0.66f, -0.72f};
  View combined = translated({-0.04, 0.03, 0.06});
  combined.pose = test::rotated(combined.pose, -4.0, 2.5);
  const std::vector<Move> moves = {
      {"translation", translated({0.05, -0.02, 0.03})},
      {"rotation", {test::rotated(now.pose, 3.0, 1.0), now.fov}},
      {"fov_and_size", wider, Extent{120, 80}},
      {"translation_rotation", combined},
      {"behind_old_eye", translated(now.pose.orientation * glm::dvec3(0.0, 0.0, -0.7))},
      {"outside_old_buffer", {test::rotated(now.pose, 25.0, -10.0), now.fov}},
  };
  WarpRig rig(ctx());
  for (const Move& move : moves) {
    SCOPED_TRACE(move.name);
    const Camera traced = Camera::with_guard_band(move.old_view, move.old_display, kGuard);
    const VisibilityBuffer vis = make_random_visibility(traced.extent.width, traced.extent.height, 5, 7);
    VisibilityInput input;
    input.buffer = &vis;
    input.traced = traced;
    const WarpResult cpu = expect_gpu_equals_cpu(rig, display, input);
    EXPECT_GT(cpu.counts[WarpStatus::kKnown], 0u);
    if (std::string(move.name) == "behind_old_eye") {
      EXPECT_GT(cpu.counts[WarpStatus::kBehind], 100u);
    }
    if (std::string(move.name) == "outside_old_buffer") {
      EXPECT_GT(cpu.counts[WarpStatus::kOutside], 1000u);
    }
  }
}

// The status and motion outputs are optional (debug, tests): leaving them out changes neither the masks nor the
// counts, and the counts (gathered per bucket of workgroups) still match the CPU reference on a display whose
// width and height are not multiples of a workgroup or a bucket.
TEST_F(ClientWarpTest, OptionalOutputsOffChangeNoMaskAndNoCount) {
  const View now = base_view();
  View old_view = now;
  old_view.pose = test::rotated(now.pose, 6.0, -2.0);
  old_view.pose.position += glm::dvec3(0.03, 0.0, -0.05);
  const Camera traced = Camera::with_guard_band(old_view, kExtent, kGuard);
  const VisibilityBuffer vis = make_random_visibility(traced.extent.width, traced.extent.height, 4, 21);
  const VisibilityInput input{&vis, traced, {}, 0};
  WarpRig rig(ctx());
  const Camera display = display_camera(now, kExtent);
  const WarpResult cpu = expect_gpu_equals_cpu(rig, display, input);
  ASSERT_GT(cpu.counts[WarpStatus::kOutside], 0u);

  std::vector<float> depth = synthetic_depth();
  remove_ambiguous(depth, reference(depth, display, input));
  const WarpResult sanitized = reference(depth, display, input);
  WarpRig bare_rig(ctx(), WarpOutputs{});
  const GpuWarp bare = bare_rig.run(depth, display, input);
  EXPECT_TRUE(bare.status.empty());
  EXPECT_EQ(bare.masks, sanitized.masks);
  EXPECT_EQ(bare.counts, sanitized.counts);

  // Odd sizes: partial workgroups and a partial bucket on both axes; 1001x301 has more count words (1,216)
  // than read_counts reads at once (512).
  WarpPass pass(ctx());
  for (const Extent odd : {Extent{1, 1}, Extent{67, 9}, Extent{131, 77}, Extent{1001, 301}}) {
    SCOPED_TRACE(std::to_string(odd.width) + "x" + std::to_string(odd.height));
    WarpTargets t = WarpTargets::create(ctx(), odd, WarpOutputs{});
    vk::Image d = GBuffer::create(ctx(), odd).depth;
    std::vector<float> values(size_t{odd.width} * odd.height);
    for (size_t i = 0; i < values.size(); ++i) values[i] = i % 7 == 0 ? 0.0f : 0.05f;  // some background
    vk::upload_image(ctx(), d, values.data(), values.size() * sizeof(float));
    const Camera odd_display = display_camera(now, odd);
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { record_warp(cmd, pass, d, odd_display, VisibilityInput{}, t); });
    const WarpCounts counts = pass.read_counts(0);
    const uint64_t background = (values.size() + 6) / 7;
    EXPECT_EQ(counts[WarpStatus::kBackground], background);
    EXPECT_EQ(counts[WarpStatus::kNoData], values.size() - background);
  }
}

TEST_F(ClientWarpTest, MissingRowsAreUnknown) {
  const View now = base_view();
  View old_view = now;
  old_view.pose.position += glm::dvec3(0.02, 0.01, 0.0);
  const Camera traced = Camera::with_guard_band(old_view, kExtent, kGuard);
  const VisibilityBuffer vis = make_random_visibility(traced.extent.width, traced.extent.height, 3, 11);
  std::vector<uint8_t> rows(traced.extent.height, 1);
  for (size_t r = 0; r < rows.size(); r += 3) rows[r] = 0;
  VisibilityInput input;
  input.buffer = &vis;
  input.traced = traced;
  input.row_valid = rows;
  WarpRig rig(ctx());
  const WarpResult cpu = expect_gpu_equals_cpu(rig, display_camera(now, kExtent), input);
  EXPECT_GT(cpu.counts[WarpStatus::kMissingRow], 1000u);
}

TEST_F(ClientWarpTest, EveryMaskWidth) {
  const View now = base_view();
  View old_view = now;
  old_view.pose = test::rotated(now.pose, 1.5, -0.5);
  const Camera traced = Camera::with_guard_band(old_view, kExtent, kGuard);
  WarpRig rig(ctx());
  for (uint32_t lights : {1u, 8u, 12u, 32u}) {
    SCOPED_TRACE(lights);
    const VisibilityBuffer vis = make_random_visibility(traced.extent.width, traced.extent.height, lights, lights);
    VisibilityInput input;
    input.buffer = &vis;
    input.traced = traced;
    expect_gpu_equals_cpu(rig, display_camera(now, kExtent), input);
  }
}

TEST_F(ClientWarpTest, IdentityReturnsTheTracedMasks) {
  const View now = base_view();
  const Camera display = display_camera(now, kExtent);
  const Camera traced = Camera::with_guard_band(now, kExtent, kGuard);
  const VisibilityBuffer vis = make_random_visibility(traced.extent.width, traced.extent.height, 9, 3);
  VisibilityInput input;
  input.buffer = &vis;
  input.traced = traced;
  WarpRig rig(ctx());
  const std::vector<float> depth = synthetic_depth();
  const GpuWarp gpu = rig.run(depth, display, input);
  for (uint32_t j = 0; j < kExtent.height; ++j) {
    for (uint32_t i = 0; i < kExtent.width; ++i) {
      const size_t p = size_t{j} * kExtent.width + i;
      if (depth[p] == 0.0f) {
        ASSERT_EQ(gpu.status[p], static_cast<uint32_t>(WarpStatus::kBackground));
        ASSERT_EQ(gpu.masks[p], vis.light_bits());
      } else {
        ASSERT_EQ(gpu.status[p], static_cast<uint32_t>(WarpStatus::kKnown)) << i << "," << j;
        ASSERT_EQ(gpu.masks[p], vis.get(i + kGuard.x, j + kGuard.y)) << i << "," << j;
      }
    }
  }
  EXPECT_EQ(gpu.counts.unknown_surface(), 0u);
  // The CPU reference agrees without any sanitizing: identity lookups sit at pixel centres.
  const WarpResult cpu = reference(depth, display, input);
  EXPECT_EQ(cpu.masks, gpu.masks);
}

TEST_F(ClientWarpTest, NoVisibilityYetMeansAllLit) {
  const Camera display = display_camera(base_view(), kExtent);
  WarpRig rig(ctx());
  const std::vector<float> depth = synthetic_depth();
  const GpuWarp gpu = rig.run(depth, display, VisibilityInput{});
  for (size_t p = 0; p < depth.size(); ++p) {
    ASSERT_EQ(gpu.masks[p], 0xFFFFFFFFu);
    ASSERT_EQ(gpu.status[p], static_cast<uint32_t>(depth[p] == 0.0f ? WarpStatus::kBackground : WarpStatus::kNoData));
  }
  EXPECT_EQ(gpu.counts.unknown_surface(), gpu.counts[WarpStatus::kNoData]);
  EXPECT_GT(gpu.counts[WarpStatus::kNoData], 0u);
}

TEST_F(ClientWarpTest, UnusableVisibilityIsIgnoredNotFatal) {
  const View now = base_view();
  const Camera traced = Camera::with_guard_band(now, kExtent, kGuard);
  const VisibilityBuffer wrong_size = make_random_visibility(traced.extent.width - 2, traced.extent.height, 3, 1);
  VisibilityInput input;
  input.buffer = &wrong_size;
  input.traced = traced;
  EXPECT_TRUE(validate_visibility_input(traced, wrong_size, {}).has_value());
  WarpPass pass(ctx());
  WarpTargets targets = WarpTargets::create(ctx(), kExtent, WarpOutputs{true, false});
  vk::Image depth = GBuffer::create(ctx(), kExtent).depth;
  const std::vector<float> values = synthetic_depth();
  vk::upload_image(ctx(), depth, values.data(), values.size() * sizeof(float));
  bool used = true;
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    used = record_warp(cmd, pass, depth, display_camera(now, kExtent), input, targets);
  });
  EXPECT_FALSE(used);
  EXPECT_EQ(pass.read_counts(0)[WarpStatus::kKnown], 0u);
  // Row validity of the wrong length is rejected the same way, and the reference throws for both.
  const VisibilityBuffer vis = make_random_visibility(traced.extent.width, traced.extent.height, 3, 1);
  const std::vector<uint8_t> rows(5, 1);
  EXPECT_TRUE(validate_visibility_input(traced, vis, rows).has_value());
  VisibilityBuffer huge;  // filled by hand, bypassing VisibilityBuffer::create's limits
  huge.width = 104;
  huge.height = kMaxBufferDimension + 8;
  huge.data.resize(huge.size_bytes());
  Camera tall = traced;
  tall.extent.height = huge.height;
  EXPECT_TRUE(validate_visibility_input(tall, huge, {}).has_value());
  WarpInput in;
  in.depth = values;
  in.display = display_camera(now, kExtent);
  in.sources[0].traced = traced;
  in.sources[0].visibility = &wrong_size;
  EXPECT_THROW(warp_reference(in), std::invalid_argument);
}

TEST_F(ClientWarpTest, FarFromTheOriginTheWarpIsUnchanged) {
  const glm::dvec3 far(1.0e4, -3.0e3, 2.0e4);
  const View now = base_view();
  View old_view = now;
  old_view.pose = test::rotated(now.pose, 2.0, 1.0);
  old_view.pose.position += glm::dvec3(0.03, -0.01, 0.02);
  View now_far = now, old_far = old_view;
  now_far.pose.position += far;
  old_far.pose.position += far;
  const Camera traced = Camera::with_guard_band(old_view, kExtent, kGuard);
  const Camera traced_far = Camera::with_guard_band(old_far, kExtent, kGuard);
  const VisibilityBuffer vis = make_random_visibility(traced.extent.width, traced.extent.height, 4, 5);
  VisibilityInput input{&vis, traced, {}, 0};
  VisibilityInput input_far{&vis, traced_far, {}, 0};
  std::vector<float> depth = synthetic_depth();
  remove_ambiguous(depth, reference(depth, display_camera(now, kExtent), input));
  WarpRig rig(ctx());
  const GpuWarp near_origin = rig.run(depth, display_camera(now, kExtent), input);
  const GpuWarp offset = rig.run(depth, display_camera(now_far, kExtent), input_far);
  EXPECT_EQ(offset.masks, near_origin.masks);
  EXPECT_EQ(offset.status, near_origin.status);
}

}  // namespace
}  // namespace dhr::render
