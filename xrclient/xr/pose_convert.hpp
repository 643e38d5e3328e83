// OpenXR pose/FOV types -> dhr::Pose / dhr::Fov / dhr::View (double precision on the CPU).
#pragma once
#include <openxr/openxr.h>

#include "core/pose.hpp"

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

}  // namespace dhr::xr
