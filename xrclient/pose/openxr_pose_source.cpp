#include "pose/openxr_pose_source.hpp"

#include <algorithm>
#include <stdexcept>

#include "log/log.hpp"
#include "xr/pose_convert.hpp"

namespace dhr::client {

TraceSample trace_sample_of(double seconds, const std::array<View, 2>& views) {
  TraceSample s;
  s.time = seconds;
  s.head.position = 0.5 * (views[0].pose.position + views[1].pose.position);
  s.head.orientation = views[0].pose.orientation;
  for (int e = 0; e < 2; ++e) {
    s.eye[e] = views[e].pose;
    s.fov[e] = views[e].fov;
  }
  return s;
}

OpenXrPoseSource::~OpenXrPoseSource() {
  std::string error;
  if (writer_.is_open() && !writer_.close(&error)) log::error("record trace: %s", error.c_str());
}

void OpenXrPoseSource::record_to(const std::string& path) {
  std::string error;
  if (!writer_.open(path, true, true, {"recorded by dhr-xrclient from OpenXR views"}, &error)) {
    throw std::runtime_error("cannot record the trace: " + error);
  }
}

void OpenXrPoseSource::set_frame(const xr::FrameState& frame) {
  FramePose s;
  s.frame = frame.index;
  s.display_time_ns = frame.predicted_display_time;
  if (!first_display_time_ns_) first_display_time_ns_ = frame.predicted_display_time;
  s.scene_time_ns = std::max<int64_t>(0, frame.predicted_display_time - *first_display_time_ns_);
  for (uint32_t e = 0; e < 2; ++e) s.views[e] = xr::to_view(frame.views[e]);
  pending_ = s;
}

bool OpenXrPoseSource::next(FramePose& out) {
  if (!pending_) return false;
  out = *pending_;
  pending_.reset();
  if (writer_.is_open()) {
    if (!first_time_ns_) first_time_ns_ = out.display_time_ns;
    const double t = static_cast<double>(out.display_time_ns - *first_time_ns_) * 1e-9;
    std::string error;
    // The writer rejects what a reader would (non-finite, time going backwards): such rows are skipped.
    if (!writer_.append(trace_sample_of(t, out.views), &error) && ++rows_skipped_ <= 5) {
      log::warn("record trace: row skipped: %s", error.c_str());
    }
  }
  return true;
}

bool OpenXrPoseSource::close_recording(std::string* out_error) {
  if (!writer_.is_open()) return true;
  return writer_.close(out_error);
}

}  // namespace dhr::client
