// Where the headset starts in the scene: an offset of the world reference space (XrReferenceSpaceCreateInfo::
// poseInReferenceSpace) that puts the head's first located pose at a chosen place and heading. Only the heading
// (rotation about +Y, the reference space's up) is turned, so the floor stays level and the user's own pitch and
// roll stay theirs.
#pragma once
#include <openxr/openxr.h>

namespace dhr::xr {

// The pose of the new world space in the runtime's reference space, such that a head located at `head` in the
// reference space is located at `start`'s position with `start`'s heading in the new space. `start`'s pitch and
// roll are ignored (its heading: the direction its -Z looks, projected onto the floor). Both quaternions unit.
XrPosef world_offset_for_start(const XrPosef& head_in_reference, const XrPosef& start);

// Every component finite (a NaN head pose gives a NaN offset, which must not reach the runtime).
bool finite_pose(const XrPosef& pose);

// The head of a stereo pair: the mid-point of the eyes, the left eye's orientation.
XrPosef head_of_views(const XrPosef& left_eye, const XrPosef& right_eye);

}  // namespace dhr::xr
