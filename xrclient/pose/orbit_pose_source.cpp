#include "pose/orbit_pose_source.hpp"

#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <numbers>

namespace dhr::client {

OrbitPoseSource::OrbitPoseSource(const TracePlacement& placement, const EyeModel& eyes, const OrbitParams& params,
                                 int64_t frame_period_ns)
    : placement_(placement), eyes_(eyes), params_(params), period_ns_(frame_period_ns) {}

Pose OrbitPoseSource::head_at(double seconds) const {
  const double phase = 2.0 * std::numbers::pi * seconds / params_.period_s;
  const double yaw = placement_.yaw_radians + params_.yaw_amplitude_rad * std::sin(phase);
  const glm::dquat q_yaw = glm::angleAxis(yaw, glm::dvec3(0.0, 1.0, 0.0));
  const glm::dquat q_pitch = glm::angleAxis(params_.pitch_rad, glm::dvec3(1.0, 0.0, 0.0));
  // Sway along the placement's own right axis (yaw 0 faces -Z, so right is +X).
  const glm::dquat q_base = glm::angleAxis(placement_.yaw_radians, glm::dvec3(0.0, 1.0, 0.0));
  const glm::dvec3 right = q_base * glm::dvec3(1.0, 0.0, 0.0);
  Pose head;
  head.position = placement_.translation + right * (params_.sway_metres * std::sin(0.5 * phase));
  head.orientation = glm::normalize(q_yaw * q_pitch);
  return head;
}

bool OrbitPoseSource::next(FramePose& out) {
  const int64_t t_ns = static_cast<int64_t>(next_frame_) * period_ns_;
  out.frame = next_frame_;
  out.display_time_ns = t_ns;
  out.scene_time_ns = t_ns;
  out.views = eyes_.views(head_at(static_cast<double>(t_ns) * 1e-9));
  ++next_frame_;
  return true;
}

}  // namespace dhr::client
