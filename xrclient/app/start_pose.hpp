// --start-at: where the OpenXR head starts in the scene (xr/world_origin.hpp offsets the world space to it).
#pragma once
#include <string>

#include "math/pose.hpp"

namespace dhr::client {

// "bookmark" (the first camera of the scene's <scene>.cameras.json), "bookmark:N" (its N-th, from 0, or the one
// named N) or "x,y,z:tx,ty,tz" (a look-at camera, metres). The pose looks from the camera at its target. Throws
// InputError naming the problem (no bookmark file, no such bookmark, a malformed spec).
Pose resolve_start_pose(const std::string& spec, const std::string& scene_path);

}  // namespace dhr::client
