#include "xr/spaces.hpp"

#include <algorithm>
#include <vector>

#include "log/log.hpp"
#include "xr/xr_check.hpp"
#include "xr/xr_struct.hpp"

namespace dhr::xr {

namespace {

XrPosef identity_pose() {
  XrPosef pose{};
  pose.orientation.w = 1.0f;
  return pose;
}

XrSpace create_space(XrSession session, XrReferenceSpaceType type, const XrPosef& pose = identity_pose()) {
  auto create_info = make_xr<XrReferenceSpaceCreateInfo>(XR_TYPE_REFERENCE_SPACE_CREATE_INFO);
  create_info.referenceSpaceType = type;
  create_info.poseInReferenceSpace = pose;
  XrSpace space = XR_NULL_HANDLE;
  DHR_XR_CHECK(xrCreateReferenceSpace(session, &create_info, &space));
  return space;
}

}  // namespace

const char* reference_space_name(XrReferenceSpaceType type) {
  switch (type) {
    case XR_REFERENCE_SPACE_TYPE_VIEW: return "VIEW";
    case XR_REFERENCE_SPACE_TYPE_LOCAL: return "LOCAL";
    case XR_REFERENCE_SPACE_TYPE_STAGE: return "STAGE";
    default: return "OTHER";
  }
}

ReferenceSpaces::ReferenceSpaces(XrSession session) : session_(session) {
  uint32_t count = 0;
  DHR_XR_CHECK(xrEnumerateReferenceSpaces(session, 0, &count, nullptr));
  std::vector<XrReferenceSpaceType> types(count);
  DHR_XR_CHECK(xrEnumerateReferenceSpaces(session, count, &count, types.data()));
  const bool has_stage =
      std::find(types.begin(), types.end(), XR_REFERENCE_SPACE_TYPE_STAGE) != types.end();
  world_type_ = has_stage ? XR_REFERENCE_SPACE_TYPE_STAGE : XR_REFERENCE_SPACE_TYPE_LOCAL;
  world_ = create_space(session, world_type_);
  try {
    view_ = create_space(session, XR_REFERENCE_SPACE_TYPE_VIEW);
  } catch (...) {
    xrDestroySpace(world_);
    throw;
  }
  dhr::log::info("openxr: world space %s", reference_space_name(world_type_));
}

void ReferenceSpaces::offset_world(const XrPosef& pose_in_reference) {
  const XrSpace replacement = create_space(session_, world_type_, pose_in_reference);
  xrDestroySpace(world_);
  world_ = replacement;
  dhr::log::info("openxr: world space %s offset to (%.3f, %.3f, %.3f)", reference_space_name(world_type_),
                 static_cast<double>(pose_in_reference.position.x), static_cast<double>(pose_in_reference.position.y),
                 static_cast<double>(pose_in_reference.position.z));
}

ReferenceSpaces::~ReferenceSpaces() {
  if (view_ != XR_NULL_HANDLE) xrDestroySpace(view_);
  if (world_ != XR_NULL_HANDLE) xrDestroySpace(world_);
}

}  // namespace dhr::xr
