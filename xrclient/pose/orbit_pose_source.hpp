// A scripted head motion for demos and offscreen runs without a trace: standing at the scene's default
// viewpoint (TracePlacement), looking down at the room, swaying sideways and turning the head slowly,
// periodic and deterministic (a function of the frame number only) on the 90 Hz virtual clock.
#pragma once
#include "traces/eye_model.hpp"
#include "pose/pose_source.hpp"

namespace dhr::client {

struct OrbitParams {
  double sway_metres = 0.15;        // sideways amplitude
  double yaw_amplitude_rad = 0.35;  // head turn amplitude (about 20 degrees)
  double pitch_rad = -0.35;         // looking down (about 20 degrees)
  double period_s = 6.0;            // one full cycle
};

class OrbitPoseSource final : public PoseSource {
 public:
  OrbitPoseSource(const TracePlacement& placement, const EyeModel& eyes, const OrbitParams& params = {},
                  int64_t frame_period_ns = kVirtualFramePeriodNs);
  bool next(FramePose& out) override;  // never ends
  std::string describe() const override { return "scripted orbit"; }
  Pose head_at(double seconds) const;

 private:
  TracePlacement placement_;
  EyeModel eyes_;
  OrbitParams params_;
  int64_t period_ns_;
  uint64_t next_frame_ = 0;
};

}  // namespace dhr::client
