// Reference spaces: the application's world space (STAGE when the runtime has one, so the floor
// is at y = 0; LOCAL otherwise) and VIEW (the head).
#pragma once
#include <openxr/openxr.h>

namespace dhr::xr {

class ReferenceSpaces {
 public:
  explicit ReferenceSpaces(XrSession session);  // throws XrError
  ~ReferenceSpaces();
  ReferenceSpaces(const ReferenceSpaces&) = delete;
  ReferenceSpaces& operator=(const ReferenceSpaces&) = delete;

  XrSpace world() const { return world_; }
  // Replaces the world space by one of the same type whose origin is `pose_in_reference` in the runtime's
  // reference space (poseInReferenceSpace; xr/world_origin.hpp computes it). Throws XrError.
  void offset_world(const XrPosef& pose_in_reference);
  XrReferenceSpaceType world_type() const { return world_type_; }
  XrSpace view() const { return view_; }

 private:
  XrSession session_ = XR_NULL_HANDLE;
  XrSpace world_ = XR_NULL_HANDLE;
  XrSpace view_ = XR_NULL_HANDLE;
  XrReferenceSpaceType world_type_ = XR_REFERENCE_SPACE_TYPE_LOCAL;
};

const char* reference_space_name(XrReferenceSpaceType type);

}  // namespace dhr::xr
