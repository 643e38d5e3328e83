// Views from the OpenXR runtime: the frame loop hands each frame's FrameState (xrLocateViews at the predicted
// display time) to set_frame(), next() returns it. Optionally records what it returns as a canonical trace
// (--record-trace) with per-eye poses and FOVs, so the session can be replayed offscreen later.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "traces/pose_trace.hpp"
#include "pose/pose_source.hpp"
#include "xr/frame_loop.hpp"

namespace dhr::client {

class OpenXrPoseSource final : public PoseSource {
 public:
  OpenXrPoseSource() = default;
  ~OpenXrPoseSource() override;

  // Throws std::runtime_error naming the file when it cannot be created.
  void record_to(const std::string& path);
  void set_frame(const xr::FrameState& frame);

  // The frame set last (false when none is pending). Recording failures are logged once and stop recording.
  bool next(FramePose& out) override;
  std::string describe() const override { return "OpenXR views"; }
  size_t rows_recorded() const { return writer_.rows(); }
  bool close_recording(std::string* out_error);

 private:
  std::optional<FramePose> pending_;
  std::optional<int64_t> first_display_time_ns_;  // the scene clock starts at the first frame's display
  PoseTraceWriter writer_;
  std::optional<int64_t> first_time_ns_;
  uint64_t rows_skipped_ = 0;  // logged for the first few only
};

// The trace row of a pair of eye views: time in seconds, head = midpoint of the eyes with the left eye's
// orientation, the eyes and FOVs as given.
TraceSample trace_sample_of(double seconds, const std::array<View, 2>& views);

}  // namespace dhr::client
