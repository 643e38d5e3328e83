#include "frame/frame_step.hpp"

#include <utility>

namespace dhr::client {

FrameStep::FrameStep(StereoPipeline& stereo, VisibilitySource& visibility, const FrameStepOptions& options)
    : stereo_(&stereo), visibility_(&visibility), options_(options), planner_(options.plan) {}

void FrameStep::take_visibility() {
  for (uint32_t e = 0; e < 2; ++e) {
    VisibilityFrame incoming;
    if (visibility_->take_newest(e, incoming)) planner_.offer(e, std::move(incoming));
  }
}

FrameRecord FrameStep::record(VkCommandBuffer cmd, uint32_t slot, const FrameInput& input) {
  take_visibility();
  const FramePose& pose = input.pose;
  const std::optional<VisibilityFormat> format = visibility_->format();
  const FramePlan plan = planner_.plan(pose, format ? std::optional<TracedFormat>(format->traced) : std::nullopt,
                                       [this](uint64_t f) { return visibility_->response_ns(f); });

  FrameRecord record;
  record.frame = pose.frame;
  record.display_time_ns = pose.display_time_ns;
  record.scene_time_ns = pose.scene_time_ns;
  record.pose_reused = input.pose_reused;
  record.response_ms = plan.response_ms;
  StereoInputs inputs;
  inputs.scene_time_ns = pose.scene_time_ns;
  inputs.node_overrides = input.node_overrides;
  inputs.shadow_owner = options_.shadow_owner;
  for (uint32_t e = 0; e < 2; ++e) {
    const EyePlan& p = plan.eyes[e];
    inputs.views[e] = p.view;
    inputs.visibility[e] = p.visibility;
    inputs.older[e] = p.older;
    if (options_.upload_keys) {
      // Non-zero and unique per (frame, eye): an unchanged complete buffer is not uploaded again; a partial one
      // may still fill in, so it is always uploaded.
      inputs.visibility[e].key = p.has_visibility && p.complete ? p.visibility_frame * 2 + e + 1 : 0;
      inputs.older[e].key = p.older.buffer != nullptr && p.older_complete ? p.older_frame * 2 + e + 1 : 0;
    }
    EyeFrameRecord& er = record.eyes[e];
    er.has_visibility = p.has_visibility;
    er.visibility_frame = p.visibility_frame;
    er.complete = p.complete;
    er.age = p.age;
    er.display_frame = p.display_frame;
    er.predicted = p.predicted;
    er.first_use = p.first_use;
    er.visibility_age_ns = p.visibility_age_ns;
    rendered_views_[e] = p.view;
  }
  stereo_->record(cmd, slot, inputs);
  return record;
}

}  // namespace dhr::client
