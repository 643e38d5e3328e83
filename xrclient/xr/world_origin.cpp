#include "xr/world_origin.hpp"

#include <cmath>
#include <initializer_list>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace dhr::xr {

namespace {

glm::dquat to_glm(const XrQuaternionf& q) { return glm::dquat(q.w, q.x, q.y, q.z); }
glm::dvec3 to_glm(const XrVector3f& v) { return glm::dvec3(v.x, v.y, v.z); }

// The rotation about +Y that turns -Z to where `q` looks, projected onto the floor (identity when it looks
// straight up or down).
glm::dquat heading(const glm::dquat& q) {
  const glm::dvec3 forward = q * glm::dvec3(0.0, 0.0, -1.0);
  if (std::abs(forward.x) < 1e-9 && std::abs(forward.z) < 1e-9) return glm::dquat(1.0, 0.0, 0.0, 0.0);
  const double yaw = std::atan2(-forward.x, -forward.z);
  return glm::angleAxis(yaw, glm::dvec3(0.0, 1.0, 0.0));
}

XrPosef to_xr(const glm::dquat& q, const glm::dvec3& p) {
  XrPosef out{};
  const glm::dquat n = glm::normalize(q);
  out.orientation = {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z), static_cast<float>(n.w)};
  out.position = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  return out;
}

}  // namespace

XrPosef world_offset_for_start(const XrPosef& head_in_reference, const XrPosef& start) {
  // world_from_reference T maps the head's position and heading onto the start's:
  //   T = [start position, start heading] * inverse([head position, head heading]).
  // The new space's pose in the reference space is inverse(T) (views located in it are T * view).
  const glm::dquat head_heading = heading(to_glm(head_in_reference.orientation));
  const glm::dquat start_heading = heading(to_glm(start.orientation));
  const glm::dquat rotation = start_heading * glm::inverse(head_heading);
  const glm::dvec3 translation = to_glm(start.position) - rotation * to_glm(head_in_reference.position);
  const glm::dquat inverse_rotation = glm::inverse(rotation);
  return to_xr(inverse_rotation, -(inverse_rotation * translation));
}

bool finite_pose(const XrPosef& pose) {
  for (const float c : {pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w, pose.position.x,
                        pose.position.y, pose.position.z})
    if (!std::isfinite(c)) return false;
  return true;
}

XrPosef head_of_views(const XrPosef& left_eye, const XrPosef& right_eye) {
  const glm::dvec3 mid = 0.5 * (to_glm(left_eye.position) + to_glm(right_eye.position));
  return to_xr(to_glm(left_eye.orientation), mid);
}

}  // namespace dhr::xr
