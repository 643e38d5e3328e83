#include "plan/frame_planner.hpp"

#include <algorithm>
#include <utility>

namespace dhr::client {

FramePlanner::FramePlanner(const PlannerSettings& settings)
    : settings_(settings), history_(settings.history_frames) {}

bool FramePlanner::offer(uint32_t eye, VisibilityFrame&& frame) {
  std::optional<VisibilityFrame>& held = held_[eye];
  if (held && held->frame_number > frame.frame_number) return false;
  offered_[eye] = frame.frame_number;
  if (held && held->frame_number < frame.frame_number) previous_[eye] = std::move(*held);
  held = std::move(frame);
  return true;
}

FramePlan FramePlanner::plan(const FramePose& pose, const std::optional<TracedFormat>& format,
                             const ResponseLookup& response) {
  history_.record(pose);
  FramePlan out;
  out.pose = pose;
  for (uint32_t e = 0; e < 2; ++e) out.eyes[e] = plan_eye(e, pose, format);
  // One response time per visibility frame, the first time it is taken (eyes in order), newer frames only.
  for (std::optional<uint64_t>& offered : offered_) {
    if (offered && response && !out.response_ms && (!responded_frame_ || *offered > *responded_frame_)) {
      if (const std::optional<int64_t> ns = response(*offered)) {
        out.response_ms = static_cast<double>(*ns) * 1e-6;
        responded_frame_ = *offered;
      }
    }
    offered.reset();
  }
  return out;
}

EyePlan FramePlanner::plan_eye(uint32_t eye, const FramePose& pose, const std::optional<TracedFormat>& format) {
  EyePlan p;
  p.view = pose.views[eye];
  p.display_frame = pose.frame;
  const std::optional<VisibilityFrame>& held = held_[eye];
  const bool usable = held && format;
  const ScheduleDecision d = decide_schedule(settings_.schedule, settings_.x_max, pose.frame,
                                             usable ? std::optional<uint64_t>(held->frame_number) : std::nullopt);
  p.age = d.age;
  if (d.display_frame != pose.frame) {
    if (const FramePose* shown = history_.find(d.display_frame)) {
      p.view = shown->views[eye];
      p.display_frame = d.display_frame;
    }
  }
  if (!usable) {
    // Nothing to warp: every surface pixel is unknown. The camera is the displayed one (as for kStale).
    if (format) p.visibility.traced = format->camera(pose.views[eye]);
    return p;
  }
  const VisibilityFrame& v = *held;
  p.has_visibility = true;
  p.visibility_frame = v.frame_number;
  p.complete = v.complete;
  p.predicted = settings_.schedule == Schedule::kStale
                    ? 0
                    : p.display_frame - std::min(p.display_frame, p.visibility_frame);
  p.visibility.buffer = &v.buffer;
  if (!v.complete) p.visibility.row_valid = v.row_valid;
  // kStale: the old bits as if they had been traced for the displayed view (no reprojection at all).
  p.visibility.traced = format->camera(settings_.schedule == Schedule::kStale ? pose.views[eye] : v.view);
  p.visibility.scene_time_ns = v.scene_time_ns;
  p.first_use = !last_used_[eye] || *last_used_[eye] != v.frame_number;
  last_used_[eye] = v.frame_number;
  if (const FramePose* traced = history_.find(v.frame_number)) {
    p.visibility_age_ns = pose.display_time_ns - traced->display_time_ns;
  }
  const std::optional<VisibilityFrame>& prev = previous_[eye];
  const Camera older_camera = prev ? format->camera(prev->view) : Camera{};
  // A buffer of another traced format (renegotiated since) is not used.
  if (prev && settings_.schedule != Schedule::kStale && older_camera.extent.width == prev->buffer.width &&
      older_camera.extent.height == prev->buffer.height) {
    p.older.buffer = &prev->buffer;
    if (!prev->complete) p.older.row_valid = prev->row_valid;
    p.older.traced = older_camera;
    p.older.scene_time_ns = prev->scene_time_ns;
    p.older_frame = prev->frame_number;
    p.older_complete = prev->complete;
  }
  return p;
}

}  // namespace dhr::client
