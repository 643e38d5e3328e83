// The client's per-frame step, between the frame loop's housekeeping (pose out, GPU slots, submission) and the
// passes: take the newest visibility per eye from the VisibilitySource, let the FramePlanner choose what each eye
// shows, record both eyes (StereoPipeline) into the frame's command buffer, and describe the frame (FrameRecord).
// FrameCoordinator runs it for the client; dhr-eval runs the same FrameCoordinator, so the evaluation measures
// this step and no copy of it.
#pragma once
#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <optional>

#include "frame/frame_record.hpp"
#include "frame/stereo_pipeline.hpp"
#include "frame/visibility_source.hpp"
#include "plan/frame_planner.hpp"

namespace dhr::client {

struct FrameInput {
  FramePose pose;  // validated by the pose layer (PoseGuard: finite, unit quaternions)
  bool pose_reused = false;
  // App-moved nodes the client sent (NodeScriptPlayer::overrides()); drawn and warped with them. Null: none.
  const NodeOverrides* node_overrides = nullptr;
};

struct FrameStepOptions {
  PlannerSettings plan;  // schedule, x_max, pose history
  // Name complete buffers by (frame, eye) so that a slot already holding one skips its upload. Off where several
  // clients' steps share one StereoPipeline (dhr-eval's settings): their frame numbers name different buffers.
  bool upload_keys = true;
  // Whose shadow maps on a shared StereoPipeline (StereoInputs::shadow_owner): dhr-eval's settings each their own.
  uint32_t shadow_owner = 0;
};

class FrameStep {
 public:
  // Keeps references to both: they must outlive the step.
  FrameStep(StereoPipeline& stereo, VisibilitySource& visibility, const FrameStepOptions& options = {});

  // Plans frame input.pose with the newest visibility and records both eyes into `cmd` with GPU slot `slot`.
  // The returned record's eyes[].stats are left empty: they are known once the slot's submission completed.
  FrameRecord record(VkCommandBuffer cmd, uint32_t slot, const FrameInput& input);

  // Records a frame's pose without rendering it (dhr-eval's warm-up), so later frames may show or warp from it.
  void record_pose(const FramePose& pose) { planner_.record(pose); }

  const FramePlanner& planner() const { return planner_; }
  // The views the last recorded frame's eye images were rendered with (the planner's choice).
  const std::array<View, 2>& rendered_views() const { return rendered_views_; }

 private:
  void take_visibility();

  StereoPipeline* stereo_;
  VisibilitySource* visibility_;
  FrameStepOptions options_;
  FramePlanner planner_;
  std::array<View, 2> rendered_views_{};
};

}  // namespace dhr::client
