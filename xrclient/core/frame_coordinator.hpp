// The client's per-frame coordinator (DESIGN.md, data flow), a thin layer over the passes:
//   pose -> VisibilitySource::send_pose -> newest visibility per eye -> schedule (which frame's pose to show)
//   -> EyePipeline::record per eye (G-buffer, prediction, shading) -> FrameSink::record -> submit
//   -> FrameSink::after_submit -> view history.
// It never waits for the network; it waits only for the GPU slot it is about to reuse (frames in flight).
// Each frame's statistics become available when that slot is reused (or at finish()), through on_frame.
#pragma once
#include <vulkan/vulkan.h>

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/frame_record.hpp"
#include "core/frame_sink.hpp"
#include "core/schedule.hpp"
#include "core/view_history.hpp"
#include "core/visibility_source.hpp"
#include "render/eye_pipeline.hpp"
#include "vk/handle.hpp"

namespace dhr::vk {
class Context;
}
namespace dhr::render {
class ClientScene;
}

namespace dhr::client {

struct CoordinatorOptions {
  Schedule schedule = Schedule::kNewest;
  uint64_t x_max = 3;              // paper schedule: frames predicted at most
  size_t history_frames = 512;     // view history ring (>= x_max + the largest expected p)
  render::EyePipelineOptions eye;  // frames_in_flight: GPU slots
  uint64_t gpu_wait_timeout_ns = 5'000'000'000;  // a slot's fence; beyond it the frame fails
};

struct FrameInput {
  uint64_t frame = 0;
  int64_t display_time_ns = 0;
  std::array<View, 2> views{};  // validated by the pose layer (finite, unit quaternions)
  bool pose_reused = false;
};

class FrameCoordinator {
 public:
  using FrameCallback = std::function<void(const FrameRecord&)>;

  // Keeps references to everything: they must outlive the coordinator.
  FrameCoordinator(const vk::Context& context, const render::ClientScene& scene, Extent eye_extent,
                   VisibilitySource& visibility, const CoordinatorOptions& options = {});
  ~FrameCoordinator();
  FrameCoordinator(const FrameCoordinator&) = delete;
  FrameCoordinator& operator=(const FrameCoordinator&) = delete;

  // Called with each frame's record once its GPU work completed (in frame order).
  void set_on_frame(FrameCallback callback) { on_frame_ = std::move(callback); }

  // Renders one frame into the sink. False (with the reason in last_error()) when the GPU failed or a slot
  // did not complete in time; the coordinator is unusable afterwards.
  bool run_frame(const FrameInput& input, FrameSink& sink);
  // Waits for every frame in flight and reports them. Safe to call more than once.
  bool finish();

  const FrameSummary& summary() const { return summary_; }
  const std::string& last_error() const { return error_; }
  Extent eye_extent() const { return extent_; }
  render::EyePipeline& eye(uint32_t index) { return *eyes_[index]; }
  const ViewHistory& history() const { return history_; }
  // The newest visibility held for an eye (what the next frame will use), if any.
  const std::optional<VisibilityFrame>& visibility(uint32_t eye) const { return held_[eye]; }

 private:
  struct Slot {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vk::Fence fence;
    bool pending = false;
    FrameRecord record;
  };
  bool record_and_submit(const FrameInput& input, FrameSink& sink);
  bool complete_slot(uint32_t slot_index);
  void take_visibility(FrameRecord& record);
  render::VisibilityInput visibility_input(uint32_t eye) const;

  const vk::Context* context_;
  VisibilitySource* visibility_;
  CoordinatorOptions options_;
  Extent extent_;
  std::array<std::unique_ptr<render::EyePipeline>, 2> eyes_;
  std::array<std::optional<VisibilityFrame>, 2> held_;
  ViewHistory history_;
  vk::CommandPool pool_;
  std::vector<Slot> slots_;
  uint64_t submitted_ = 0;
  std::optional<uint64_t> responded_frame_;
  FrameCallback on_frame_;
  FrameSummary summary_;
  std::string error_;
};

// The guard-banded camera a visibility buffer was traced for: the traced view's FOV over the displayed part
// of the buffer (buffer minus guard band), widened by the guard band (projection.hpp, Camera::with_guard_band).
Camera traced_camera(const View& view, const VisibilityFormat& format);

}  // namespace dhr::client
