// The client's frame policy, free of Vulkan: given the newest visibility received per eye, the history of
// rendered poses and the settings, it decides per frame what each eye renders (DESIGN.md, terms):
// which visibility frame, p and x, the view to render the G-buffer with and to submit to the compositor, and
// the camera the visibility was traced for. It also keeps the response bookkeeping (which visibility frame
// is used for the first time). FrameCoordinator (the client's frame loop) and dhr-eval both call it, so the
// evaluation measures the client's own policy.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <optional>

#include "codec/visibility_frame.hpp"
#include "math/pose.hpp"
#include "math/projection.hpp"
#include "plan/schedule.hpp"
#include "plan/view_history.hpp"
#include "plan/visibility_input.hpp"

namespace dhr::client {

struct PlannerSettings {
  Schedule schedule = Schedule::kNewest;
  uint64_t x_max = 3;           // kPaper: frames the warp spans at most
  size_t history_frames = 512;  // pose history ring (>= x_max + the largest expected p)
};

struct EyePlan {
  View view;                    // render the G-buffer with this view, and submit the image with it
  uint64_t display_frame = 0;   // the frame whose view that is
  VisibilityInput visibility;   // what the warp reads (buffer null: nothing usable received yet)
  bool has_visibility = false;
  uint64_t visibility_frame = 0;
  bool complete = true;         // the visibility buffer arrived whole
  uint64_t age = 0;             // p: frames between the visibility and this frame
  uint64_t predicted = 0;       // x: frames the warp spans (display_frame - visibility_frame; 0 for kStale)
  bool first_use = false;       // this eye uses visibility_frame for the first time
  std::optional<int64_t> visibility_age_ns;  // display time of this frame minus that of visibility_frame
  // This eye's previous visibility (the frame held before visibility_frame; the warp's older-buffer fill):
  // buffer null when none is held or the schedule is kStale.
  VisibilityInput older;
  uint64_t older_frame = 0;
  bool older_complete = true;
};

struct FramePlan {
  FramePose pose;               // the frame being rendered (frame n)
  std::array<EyePlan, 2> eyes;
  // Response time (pose sent -> that frame's visibility complete, from the ResponseLookup) of a visibility
  // frame taken for this frame and newer than every frame measured before: at most one per frame, and one per
  // visibility frame.
  std::optional<double> response_ms;
};

// Pose sent -> visibility of that frame complete, nanoseconds; std::nullopt when not known (yet).
using ResponseLookup = std::function<std::optional<int64_t>(uint64_t frame)>;

class FramePlanner {
 public:
  explicit FramePlanner(const PlannerSettings& settings);

  // Offers a newly received visibility frame of an eye. The newest wins: a frame older than the one held
  // (reordering across reconnects) is ignored and false is returned. A newer frame moves the one held to
  // previous(eye).
  bool offer(uint32_t eye, VisibilityFrame&& frame);

  // Records a frame's pose in the history without planning it (plan() records too). For callers that do not
  // render every frame (dhr-eval's warm-up).
  void record(const FramePose& pose) { history_.record(pose); }

  // Records the pose of frame n in the history and plans the frame. `format`: the session's traced format,
  // std::nullopt before one was agreed (held visibility is then not used). `response`: where response times
  // come from (the network client); empty: none are measured. The plan's visibility inputs point into the held
  // frames: valid until the next offer(). Their upload keys are left 0 (the caller owns the upload cache).
  FramePlan plan(const FramePose& pose, const std::optional<TracedFormat>& format,
                 const ResponseLookup& response = {});

  // The newest visibility held for an eye (what the next frame will use), if any.
  const std::optional<VisibilityFrame>& held(uint32_t eye) const { return held_[eye]; }
  // The one held before it, if any.
  const std::optional<VisibilityFrame>& previous(uint32_t eye) const { return previous_[eye]; }
  const ViewHistory& history() const { return history_; }
  const PlannerSettings& settings() const { return settings_; }

 private:
  EyePlan plan_eye(uint32_t eye, const FramePose& pose, const std::optional<TracedFormat>& format);

  PlannerSettings settings_;
  ViewHistory history_;
  std::array<std::optional<VisibilityFrame>, 2> held_;
  std::array<std::optional<VisibilityFrame>, 2> previous_;
  std::array<std::optional<uint64_t>, 2> last_used_;  // per eye: the visibility frame used last
  std::array<std::optional<uint64_t>, 2> offered_;  // per eye: accepted by offer() since the last plan()
  std::optional<uint64_t> responded_frame_;          // the newest frame whose response time was measured
};

}  // namespace dhr::client
