// Plays a recorded head-motion trace (shared/traces/include/traces/pose_trace.hpp, any supported format) on a 90 Hz virtual
// clock: frame i shows the trace at start_time + i * period, through the eye model (or the trace's own eye
// poses and FOVs), placed in the scene (TracePlacement). Ends after the trace's last sample.
#pragma once
#include <string>

#include "traces/eye_model.hpp"
#include "traces/pose_trace.hpp"
#include "pose/pose_source.hpp"

namespace dhr::client {

class TracePoseSource final : public PoseSource {
 public:
  // Requires a non-empty trace.
  TracePoseSource(PoseTrace trace, const EyeModel& eyes, const TracePlacement& placement, std::string name,
                  int64_t frame_period_ns = kVirtualFramePeriodNs);

  // Reads the file (format detected); throws std::runtime_error with "<file>:<line>: <problem>" or
  // "<file>: empty trace".
  static PoseTrace load(const std::string& path);

  bool next(FramePose& out) override;
  std::string describe() const override;
  uint64_t frame_count() const;  // frames until the trace ends

 private:
  PoseTrace trace_;
  EyeModel eyes_;
  Pose T_scene_trace_;
  std::string name_;
  int64_t period_ns_;
  uint64_t next_frame_ = 0;
};

}  // namespace dhr::client
