#include "math/pose.hpp"

#include <cmath>
#include <string>

namespace dhr {

glm::dmat4 Pose::matrix() const {
  glm::dmat4 m = glm::mat4_cast(orientation);
  m[3] = glm::dvec4(position, 1.0);
  return m;
}

glm::dmat4 Pose::inverse_matrix() const { return inverse().matrix(); }

Pose Pose::operator*(const Pose& rhs) const {
  Pose out;
  out.orientation = orientation * rhs.orientation;
  out.position = position + orientation * rhs.position;
  return out;
}

Pose Pose::inverse() const {
  Pose out;
  out.orientation = glm::conjugate(orientation);
  out.position = -(out.orientation * position);
  return out;
}

glm::dvec3 Pose::transform_point(const glm::dvec3& p) const { return position + orientation * p; }

namespace {
bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

std::optional<std::string> validate_pose(const Pose& pose) {
  const glm::dquat& q = pose.orientation;
  if (!finite3(pose.position)) return "pose position is not finite";
  if (!std::isfinite(q.w) || !std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
    return "pose orientation is not finite";
  const double norm2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  if (!(norm2 > 1e-12)) return "pose orientation is a zero quaternion";
  // Finite components whose squares overflow (|q| > ~1e154) normalize to zeros or NaN.
  if (!std::isfinite(norm2)) return "pose orientation is too large to normalize";
  if (glm::length(pose.position) > kMaxPositionMetres)
    return "pose position is farther than " + std::to_string(kMaxPositionMetres) + " m from the origin";
  return std::nullopt;
}

std::optional<std::string> validate_fov(const Fov& fov) {
  const float a[4] = {fov.angle_left, fov.angle_right, fov.angle_up, fov.angle_down};
  for (float v : a) {
    if (!std::isfinite(v)) return "field of view angle is not finite";
    // tan() of the angle must stay finite and the view must not wrap around.
    if (std::fabs(v) >= 1.5707f) return "field of view angle reaches 90 degrees or more";
  }
  if (!(fov.angle_left < fov.angle_right)) return "field of view: angle_left must be < angle_right";
  if (!(fov.angle_down < fov.angle_up)) return "field of view: angle_down must be < angle_up";
  return std::nullopt;
}

std::optional<std::string> validate_view(const View& view) {
  if (auto err = validate_pose(view.pose)) return err;
  return validate_fov(view.fov);
}

Pose normalized(const Pose& pose) {
  Pose out = pose;
  out.orientation = glm::normalize(pose.orientation);
  return out;
}

}  // namespace dhr
