// Issue 5 "Done when" (a) and (b): the client's frame loop (FrameCoordinator) with the real passes on
// lavapipe and the real tracer; and the loop over a StereoPipeline shared between loops (dhr-eval's settings).
//  (a) zero delay, over loopback UDP with the real VisibilityService: the presented image equals shading with
//      freshly traced visibility for the same pose, and the visibility is bit-exact.
//  (b) 100 ms delay (9 frames at 90 Hz), a recorded 6-DoF trace: the predicted visibility has fewer wrong
//      bits against the ground truth (Embree, displayed pose) than the stale buffer used as-is.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <memory>
#include <thread>

#include "traces/eye_model.hpp"
#include "frame/frame_coordinator.hpp"
#include "frame/network_visibility_source.hpp"
#include "loopback_rig.hpp"
#include "pose/orbit_pose_source.hpp"
#include "pose/trace_pose_source.hpp"
#include "render/client_scene.hpp"
#include "render/offscreen_sink.hpp"
#include "vk/context.hpp"
#include "vk/image.hpp"

namespace dhr::client {
namespace {

constexpr Extent kEye{96, 80};
constexpr GuardBand kGuard{4, 3};  // per side

std::unique_ptr<vk::Context> make_context() {
  vk::ContextOptions options;
  options.device = vk::DevicePreference::kLavapipe;
  options.validation = true;
  return vk::Context::create(options);
}

// The frame loop's defaults plus the per-pixel warp status, which CaptureSink reads back.
CoordinatorOptions capture_options() {
  CoordinatorOptions options;
  options.eye.warp_status = true;
  return options;
}

// Captures both presented eye images (readback after each frame) and what the warp pass wrote.
class CaptureSink final : public FrameSink {
 public:
  CaptureSink(const vk::Context& context, FrameCoordinator*& coordinator) : context_(context), coord_(coordinator) {}
  void after_submit(uint64_t /*frame*/, const EyeImages& eyes) override {
    for (uint32_t e = 0; e < 2; ++e) {
      images[e] = render::read_rgba8(context_, *eyes[e]);
      render::WarpTargets& p = coord_->eye(e).warp();
      masks[e].assign(size_t{kEye.width} * kEye.height, 0);
      status[e].assign(masks[e].size(), 0);
      vk::read_image(context_, p.mask, masks[e].data(), masks[e].size() * 4);
      vk::read_image(context_, p.status, status[e].data(), status[e].size() * 4);
    }
  }
  std::array<std::vector<uint8_t>, 2> images;
  std::array<std::vector<uint32_t>, 2> masks;
  std::array<std::vector<uint32_t>, 2> status;

 private:
  const vk::Context& context_;
  FrameCoordinator*& coord_;
};

std::array<View, 2> room_views() {
  OrbitPoseSource orbit(default_trace_placement(std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room.gltf"),
                        EyeModel::monado_simulated());
  FramePose s;
  orbit.next(s);
  return s.views;
}

TEST(ClientFrameLoopTest, ZeroDelayPresentsFreshlyTracedVisibility) {
  integration::TracedScene& traced = integration::TracedScene::get();
  integration::LoopbackServer server(*traced.tracer);
  UdpVisibilityClient link;
  VisibilityClientConfig config;
  config.format = TracedFormat{kEye, kGuard};
  link.connect(config, "127.0.0.1", server.port());
  NetworkVisibilitySource source(link.client());

  auto context = make_context();
  {
    const render::ClientScene scene(*context, traced.scene);
    FrameCoordinator* coord_ptr = nullptr;
    FrameCoordinator coordinator(*context, scene, kEye, source, capture_options());
    coord_ptr = &coordinator;
    CaptureSink sink(*context, coord_ptr);
    const std::array<View, 2> views = room_views();
    // A still head: once both eyes have visibility, it is for exactly this pose (zero delay in effect).
    uint64_t frame = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!(coordinator.visibility(0) && coordinator.visibility(1)) && std::chrono::steady_clock::now() < deadline) {
      link.client().tick();
      FrameInput in{FramePose{frame, static_cast<int64_t>(frame) * kVirtualFramePeriodNs, views}, false};
      ++frame;
      ASSERT_TRUE(coordinator.run_frame(in, sink)) << coordinator.last_error();
      std::this_thread::sleep_for(std::chrono::milliseconds(11));
    }
    ASSERT_TRUE(coordinator.visibility(0) && coordinator.visibility(1)) << "no visibility within 30 s";
    FrameInput last{FramePose{frame, static_cast<int64_t>(frame) * kVirtualFramePeriodNs, views}, false};
    ASSERT_TRUE(coordinator.run_frame(last, sink));
    ASSERT_TRUE(coordinator.finish());

    // Fresh: trace the same pose directly and shade it with a separate pipeline.
    const VisibilityFormat format = *source.format();
    for (uint32_t e = 0; e < 2; ++e) {
      const VisibilityFrame& used = *coordinator.visibility(e);
      ASSERT_TRUE(used.complete);
      const Camera camera = format.traced.camera(views[e]);
      VisibilityBuffer fresh;
      server::TraceStats stats;
      traced.tracer->trace(camera, fresh, stats);
      EXPECT_EQ(fresh, used.buffer) << "eye " << e << ": visibility not bit-exact";

      render::EyePipeline pipeline(*context, scene, kEye, capture_options().eye);  // the same path
      VisibilityInput input;
      input.buffer = &fresh;
      input.traced = camera;
      context->submit_and_wait([&](VkCommandBuffer cmd) { pipeline.record(cmd, 0, views[e], input); });
      const std::vector<uint8_t> expected = render::read_rgba8(*context, pipeline.output());
      EXPECT_EQ(expected, sink.images[e]) << "eye " << e << ": presented shading differs";
      const render::EyeStats s = pipeline.read_stats(0);
      EXPECT_EQ(s.unknown_pixels(), 0u);
      EXPECT_GT(s.warp[render::WarpStatus::kKnown], 0u);
    }
  }
  link.close();
  server.stop();
  EXPECT_EQ(context->validation_error_count(), 0u);
}

// The tracer in process with a fixed delay in frames: what the client would get over a network whose round
// trip is `delay` frames, deterministically.
class DelayedTracerSource final : public VisibilitySource {
 public:
  DelayedTracerSource(server::VisibilityTracer& tracer, VisibilityFormat format, uint64_t delay)
      : tracer_(tracer), format_(format), delay_(delay) {}
  void tick() override {}
  std::optional<VisibilityFormat> format() const override { return format_; }
  bool failed() const override { return false; }
  std::string failure() const override { return {}; }
  void send_pose(const FramePose& pose) override {
    current_ = pose.frame;
    const std::array<View, 2>& views = pose.views;
    Sent s{pose.frame, views, {}};
    for (uint32_t e = 0; e < 2; ++e) {
      server::TraceStats stats;
      tracer_.trace(format_.traced.camera(views[e]), s.buffers[e], stats);
    }
    queue_.push_back(std::move(s));
  }
  bool take_newest(uint32_t eye, VisibilityFrame& out) override {
    const Sent* newest = nullptr;
    for (const Sent& s : queue_) {
      if (s.frame + delay_ <= current_) newest = &s;
    }
    if (newest == nullptr || (taken_[eye] && *taken_[eye] >= newest->frame)) return false;
    out.frame_number = newest->frame;
    out.view = newest->views[eye];
    out.buffer = newest->buffers[eye];
    out.complete = true;
    taken_[eye] = newest->frame;
    while (queue_.size() > delay_ + 2) queue_.pop_front();
    return true;
  }
  std::optional<int64_t> response_ns(uint64_t) const override {
    return static_cast<int64_t>(delay_) * kVirtualFramePeriodNs;
  }
  VisibilitySourceStats stats() const override { return {}; }

 private:
  struct Sent {
    uint64_t frame;
    std::array<View, 2> views;
    std::array<VisibilityBuffer, 2> buffers;
  };
  server::VisibilityTracer& tracer_;
  VisibilityFormat format_;
  uint64_t delay_;
  uint64_t current_ = 0;
  std::deque<Sent> queue_;
  std::array<std::optional<uint64_t>, 2> taken_;
};

// The paper's schedule renders frame n - p + x with that frame's views: the images must be submitted with
// exactly those views (not frame n's), or the compositor reprojects them from the wrong pose.
TEST(ClientFrameLoopTest, PaperScheduleSubmitsTheViewsItRenderedWith) {
  integration::TracedScene& traced = integration::TracedScene::get();
  const VisibilityFormat format{TracedFormat{kEye, kGuard}, traced.tracer->light_count()};
  constexpr uint64_t kDelayFrames = 6;
  DelayedTracerSource source(*traced.tracer, format, kDelayFrames);
  auto context = make_context();
  {
    const render::ClientScene scene(*context, traced.scene);
    CoordinatorOptions options = capture_options();
    options.plan.schedule = Schedule::kPaper;
    options.plan.x_max = 2;
    FrameCoordinator* coord_ptr = nullptr;
    FrameCoordinator coordinator(*context, scene, kEye, source, options);
    coord_ptr = &coordinator;
    CaptureSink sink(*context, coord_ptr);
    std::vector<FramePose> poses;
    uint64_t checked = 0;
    for (uint64_t f = 0; f < 20; ++f) {
      FramePose pose{f, static_cast<int64_t>(f) * kVirtualFramePeriodNs, {}};
      for (uint32_t e = 0; e < 2; ++e) {  // the head slides sideways: every frame's views differ
        pose.views[e].pose.position = glm::dvec3(0.03 * static_cast<double>(f) + (e == 0 ? -0.032 : 0.032), 1.6, 1.0);
      }
      poses.push_back(pose);
      ASSERT_TRUE(coordinator.run_frame(FrameInput{pose, false}, sink)) << coordinator.last_error();
      if (!coordinator.visibility(0)) continue;
      // p = 6 frames behind, x = 2: frame n - 4 is rendered, and submitted.
      const uint64_t shown = f - kDelayFrames + 2;
      for (uint32_t e = 0; e < 2; ++e) {
        EXPECT_EQ(coordinator.rendered_views()[e].pose.position, poses[shown].views[e].pose.position) << "frame " << f;
        EXPECT_NE(coordinator.rendered_views()[e].pose.position, pose.views[e].pose.position) << "frame " << f;
      }
      ++checked;
    }
    EXPECT_GE(checked, 10u);
    ASSERT_TRUE(coordinator.finish());
  }
  EXPECT_EQ(context->validation_error_count(), 0u);
}

// Reads both presented eye images back after each frame.
class ImageSink final : public FrameSink {
 public:
  explicit ImageSink(const vk::Context& context) : context_(context) {}
  void after_submit(uint64_t /*frame*/, const EyeImages& eyes) override {
    for (uint32_t e = 0; e < 2; ++e) images[e] = render::read_rgba8(context_, *eyes[e]);
  }
  std::array<std::vector<uint8_t>, 2> images;

 private:
  const vk::Context& context_;
};

// dhr-eval runs every setting's frame loop over one shared StereoPipeline (one GPU slot, upload keys off). Frame
// for frame that must render exactly what a frame loop with its own pipelines renders (two slots, upload keys
// on), here with the full warp: the other eye's and the previous buffer, traced depths the shared pipelines hold
// for whichever loop rendered them last, shadow maps.
TEST(ClientFrameLoopTest, SharedStereoPipelineRendersAsOwnPipelines) {
  integration::TracedScene& traced = integration::TracedScene::get();
  const VisibilityFormat format{TracedFormat{kEye, kGuard}, traced.tracer->light_count()};
  auto context = make_context();
  {
    const render::ClientScene scene(*context, traced.scene);
    CoordinatorOptions own;
    own.eye.warp = render::WarpSettings::full();
    render::EyePipelineOptions shared_eye = own.eye;
    shared_eye.frames_in_flight = 1;
    StereoPipeline shared(*context, scene, kEye, shared_eye);
    CoordinatorOptions borrowed = own;
    borrowed.upload_keys = false;
    constexpr std::array<uint64_t, 2> kDelays = {2, 5};
    std::vector<std::unique_ptr<DelayedTracerSource>> sources;
    std::vector<std::unique_ptr<FrameCoordinator>> loops;  // own pipelines for both delays, then shared ones
    for (size_t k = 0; k < 4; ++k) {
      sources.push_back(std::make_unique<DelayedTracerSource>(*traced.tracer, format, kDelays[k % 2]));
      loops.push_back(k < 2 ? std::make_unique<FrameCoordinator>(*context, scene, kEye, *sources[k], own)
                            : std::make_unique<FrameCoordinator>(*context, shared, *sources[k], borrowed));
    }
    ImageSink sink(*context);
    for (uint64_t f = 0; f < 12; ++f) {
      FramePose pose{f, static_cast<int64_t>(f) * kVirtualFramePeriodNs, {}};
      for (uint32_t e = 0; e < 2; ++e) {  // the head slides sideways: every frame's views differ
        pose.views[e].pose.position = glm::dvec3(0.02 * static_cast<double>(f) + (e == 0 ? -0.032 : 0.032), 1.6, 1.0);
      }
      std::array<std::array<std::vector<uint8_t>, 2>, 4> images;
      for (size_t k = 0; k < 4; ++k) {
        ASSERT_TRUE(loops[k]->run_frame(FrameInput{pose, false}, sink)) << loops[k]->last_error();
        // A shared pipeline's statistics are per slot: read before another loop records on it.
        if (k >= 2) {
          ASSERT_TRUE(loops[k]->finish()) << loops[k]->last_error();
        }
        images[k] = sink.images;
      }
      for (size_t k = 0; k < 2; ++k) {
        for (uint32_t e = 0; e < 2; ++e) {
          EXPECT_EQ(images[k][e], images[k + 2][e]) << "frame " << f << ", delay " << kDelays[k] << ", eye " << e;
        }
      }
    }
    for (auto& loop : loops) ASSERT_TRUE(loop->finish()) << loop->last_error();
    for (size_t k = 0; k < 2; ++k) {
      const FrameSummary& a = loops[k]->summary();
      const FrameSummary& b = loops[k + 2]->summary();
      EXPECT_GE(a.frames_with_visibility(), 6u);
      EXPECT_EQ(a.frames_with_visibility(), b.frames_with_visibility());
      EXPECT_EQ(a.predicted_frac(), b.predicted_frac());
      EXPECT_EQ(a.pixels_other_eye(), b.pixels_other_eye());
      EXPECT_EQ(a.pixels_older(), b.pixels_older());
      EXPECT_EQ(a.pixels_shadow_map(), b.pixels_shadow_map());
    }
  }
  EXPECT_EQ(context->validation_error_count(), 0u);
}

TEST(ClientFrameLoopTest, PredictionBeatsStaleBufferUnderDelayOnRecordedTrace) {
  const std::filesystem::path trace_path =
      std::filesystem::path(DHR_SHARED_DATA_DIR) / "traces/6dof/gul2020_hololens/raw/User1.csv";
  if (!std::filesystem::exists(trace_path)) GTEST_SKIP() << "no recorded 6-DoF trace at " << trace_path;
  integration::TracedScene& traced = integration::TracedScene::get();
  const std::string scene_path = std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room.gltf";
  // A stretch with head motion: skip the recording's first seconds.
  PoseTrace trace = TracePoseSource::load(trace_path.string());
  trace = truncate_trace(trace, 30.0);
  TracePoseSource poses(std::move(trace), EyeModel::monado_simulated(), default_trace_placement(scene_path), "User1");

  const VisibilityFormat format{TracedFormat{kEye, kGuard}, traced.tracer->light_count()};
  constexpr uint64_t kDelayFrames = 9;  // 100 ms at 90 Hz
  DelayedTracerSource source(*traced.tracer, format, kDelayFrames);
  auto context = make_context();
  uint64_t wrong_predicted = 0;
  uint64_t wrong_stale = 0;
  uint64_t compared = 0;
  {
    const render::ClientScene scene(*context, traced.scene);
    FrameCoordinator* coord_ptr = nullptr;
    FrameCoordinator coordinator(*context, scene, kEye, source, capture_options());
    coord_ptr = &coordinator;
    CaptureSink sink(*context, coord_ptr);
    FramePose sample;
    // 2.5 s of the trace from 10 s in, every 3rd frame compared (the ground truth is traced per frame).
    for (uint64_t i = 0; i < 1125 && poses.next(sample); ++i) {
      if (i < 900) continue;
      FrameInput in{sample, false};
      ASSERT_TRUE(coordinator.run_frame(in, sink)) << coordinator.last_error();
      if (i % 3 != 0 || !coordinator.visibility(0) || !coordinator.visibility(1)) continue;
      for (uint32_t e = 0; e < 2; ++e) {
        const VisibilityFrame& stale = *coordinator.visibility(e);
        if (stale.frame_number + kDelayFrames > sample.frame) continue;  // taken before this frame
        VisibilityBuffer truth;
        server::TraceStats stats;
        traced.tracer->trace(Camera::with_guard_band(sample.views[e], kEye, GuardBand{}), truth, stats);
        for (uint32_t y = 0; y < kEye.height; ++y) {
          for (uint32_t x = 0; x < kEye.width; ++x) {
            const size_t p = size_t{y} * kEye.width + x;
            if (sink.status[e][p] == static_cast<uint32_t>(render::WarpStatus::kBackground)) continue;
            const uint32_t t = truth.get(x, y);
            const uint32_t as_is = stale.buffer.get(x + kGuard.x, y + kGuard.y);
            wrong_predicted += static_cast<uint64_t>(__builtin_popcount(sink.masks[e][p] ^ t));
            wrong_stale += static_cast<uint64_t>(__builtin_popcount(as_is ^ t));
            ++compared;
          }
        }
      }
    }
    ASSERT_TRUE(coordinator.finish());
  }
  std::printf("{\"compared_pixels\":%llu,\"wrong_bits_predicted\":%llu,\"wrong_bits_stale\":%llu}\n",
              static_cast<unsigned long long>(compared), static_cast<unsigned long long>(wrong_predicted),
              static_cast<unsigned long long>(wrong_stale));
  ASSERT_GT(compared, 10000u);
  ASSERT_GT(wrong_stale, 0u) << "the trace stretch has no motion: the comparison cannot fail";
  EXPECT_LT(wrong_predicted, wrong_stale);
  EXPECT_EQ(context->validation_error_count(), 0u);
}

}  // namespace
}  // namespace dhr::client
