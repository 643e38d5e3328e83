// The client's per-frame coordinator (DESIGN.md, data flow), a thin layer over the frame step and the passes:
//   pose -> VisibilitySource::send_pose -> FrameStep (newest visibility per eye -> FramePlanner -> both eyes'
//   passes, StereoPipeline) -> FrameSink::record -> submit -> FrameSink::after_submit.
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

#include "frame/frame_record.hpp"
#include "frame/frame_sink.hpp"
#include "frame/frame_step.hpp"
#include "frame/stereo_pipeline.hpp"
#include "frame/visibility_source.hpp"
#include "plan/frame_planner.hpp"
#include "render/eye_pipeline.hpp"
#include "render/shadow_maps.hpp"
#include "vk/handle.hpp"

namespace dhr::vk {
class Context;
}
namespace dhr::render {
class ClientScene;
}

namespace dhr::client {

struct CoordinatorOptions {
  PlannerSettings plan;            // schedule, x_max, pose history
  render::EyePipelineOptions eye;  // frames_in_flight: GPU slots; eye.warp: the warp's ingredients
  render::ShadowMapSettings shadow_maps;  // used when eye.warp needs shadow maps
  uint64_t gpu_wait_timeout_ns = 5'000'000'000;  // a slot's fence; beyond it the frame fails
  bool upload_keys = true;  // FrameStepOptions::upload_keys
  uint32_t shadow_owner = 0;  // FrameStepOptions::shadow_owner
};

class FrameCoordinator {
 public:
  using FrameCallback = std::function<void(const FrameRecord&)>;

  // Keeps references to everything: they must outlive the coordinator.
  FrameCoordinator(const vk::Context& context, const render::ClientScene& scene, Extent eye_extent,
                   VisibilitySource& visibility, const CoordinatorOptions& options = {});
  // Renders with a StereoPipeline owned elsewhere (dhr-eval: one per run, shared by its settings' coordinators),
  // with as many GPU slots as it has; options.eye and options.shadow_maps are not used. Where several
  // coordinators share it, each must finish() its frame before another records (the GPU statistics are per slot)
  // and leave options.upload_keys off.
  FrameCoordinator(const vk::Context& context, StereoPipeline& stereo, VisibilitySource& visibility,
                   const CoordinatorOptions& options = {});
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
  Extent eye_extent() const { return stereo_->extent(); }
  render::EyePipeline& eye(uint32_t index) { return stereo_->eye(index); }
  const render::EyePipeline& eye(uint32_t index) const { return stereo_->eye(index); }
  const ViewHistory& history() const { return step_.planner().history(); }
  // The newest visibility held for an eye (what the next frame will use), if any.
  const std::optional<VisibilityFrame>& visibility(uint32_t eye) const { return step_.planner().held(eye); }
  // The one held before it (the warp's older buffer), if any.
  const std::optional<VisibilityFrame>& previous_visibility(uint32_t eye) const {
    return step_.planner().previous(eye);
  }
  // The views the last frame's eye images were rendered with (the planner's choice): what the compositor
  // must be given with those images.
  const std::array<View, 2>& rendered_views() const { return step_.rendered_views(); }
  // Records a frame's pose without rendering it (dhr-eval's warm-up frames).
  void record_pose(const FramePose& pose) { step_.record_pose(pose); }
  // What the planner chose for the last submitted frame, for sinks that describe the images they are given (in
  // after_submit). Its GPU statistics are not known yet: `eyes[].stats` are filled when its slot completes.
  const FrameRecord& last_submitted() const { return slots_[last_slot_].record; }
  // The session's format (traced size and guard band, lights, scene hash), once the server has answered.
  std::optional<VisibilityFormat> visibility_format() const { return visibility_->format(); }

 private:
  struct Slot {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vk::Fence fence;
    bool pending = false;
    FrameRecord record;
  };
  bool record_and_submit(const FrameInput& input, FrameSink& sink);
  bool complete_slot(uint32_t slot_index);
  void create_slots(uint32_t count);

  const vk::Context* context_;
  VisibilitySource* visibility_;
  CoordinatorOptions options_;
  std::unique_ptr<StereoPipeline> own_stereo_;  // null when the StereoPipeline is borrowed
  StereoPipeline* stereo_;
  FrameStep step_;
  uint32_t last_slot_ = 0;  // the slot of the last submitted frame
  vk::CommandPool pool_;
  std::vector<Slot> slots_;
  uint64_t submitted_ = 0;
  FrameCallback on_frame_;
  FrameSummary summary_;
  std::string error_;
};

}  // namespace dhr::client
