// OpenXR pose/FOV types -> dhr::Pose / dhr::Fov / dhr::View (double precision on the CPU).
#pragma once
#include <openxr/openxr.h>

#include "math/pose.hpp"

namespace dhr::xr {

inline Pose to_pose(const XrPosef& pose) {
  Pose out;
  out.position = {pose.position.x, pose.position.y, pose.position.z};
  out.orientation = glm::dquat(pose.orientation.w, pose.orientation.x, pose.orientation.y,
                               pose.orientation.z);
  return out;
}

inline Fov to_fov(const XrFovf& fov) {
  return Fov{fov.angleLeft, fov.angleRight, fov.angleUp, fov.angleDown};
}

inline View to_view(const XrView& view) { return View{to_pose(view.pose), to_fov(view.fov)}; }

// dhr::View -> XrView (float precision, as the runtime takes it).
inline XrView to_xr_view(const View& view) {
  XrView out{};
  out.type = XR_TYPE_VIEW;
  out.pose.position = {static_cast<float>(view.pose.position.x), static_cast<float>(view.pose.position.y),
                       static_cast<float>(view.pose.position.z)};
  out.pose.orientation = {static_cast<float>(view.pose.orientation.x), static_cast<float>(view.pose.orientation.y),
                          static_cast<float>(view.pose.orientation.z), static_cast<float>(view.pose.orientation.w)};
  out.fov = XrFovf{view.fov.angle_left, view.fov.angle_right, view.fov.angle_up, view.fov.angle_down};
  return out;
}

}  // namespace dhr::xr
