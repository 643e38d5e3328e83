// Camera bookmarks: named look-at cameras stored beside a scene as "<scene>.cameras.json"
//   {"scene": "living_room.glb", "up": [0,1,0], "yfov_deg_suggested": 60,
//    "cameras": [{"name": "doorway_overview", "position": [x,y,z], "target": [x,y,z]}, ...]}
// or given on the command line as "x,y,z:tx,ty,tz"; and the eye views made from them.
#pragma once
#include "math/pose.hpp"
#include "math/projection.hpp"
#include "scene/scene.hpp"

#include <glm/vec3.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dhr {

struct CameraBookmark {
  std::string name;
  glm::dvec3 position{0.0};
  glm::dvec3 target{0.0, 0.0, -1.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
};

// ".../living_room.glb" -> ".../living_room.cameras.json" (the extension replaced).
std::string camera_bookmarks_path(const std::string& scene_path);

// Reads a bookmark file. std::nullopt with "<file>: <problem>" in out_error for a missing or malformed file
// (wrong JSON types, non-finite numbers, position == target, no cameras).
std::optional<std::vector<CameraBookmark>> load_camera_bookmarks(const std::string& path, std::string* out_error);

// For a scene without bookmarks: "bbox_front", looking at the bounds' centre from the front (+Z) and a
// little above, at the distance where the bounding sphere just fits the vertical field of view of a 16:9
// eye at 90 degrees horizontal.
CameraBookmark front_bookmark(const SceneBounds& bounds);

// "x,y,z:tx,ty,tz" (metres, world space); the name is left empty.
std::optional<CameraBookmark> parse_camera_spec(std::string_view spec, std::string* out_error);

// The head pose looking from bookmark.position at bookmark.target (no roll relative to `up`).
// std::nullopt when the direction is zero or parallel to up.
std::optional<Pose> look_at_pose(const CameraBookmark& bookmark);

// Symmetric FOV with the given horizontal angle; the vertical angle follows the display's aspect ratio
// (square pixels). Requires 0 < horizontal_deg < 180 and a non-empty display.
Fov symmetric_fov(double horizontal_deg, Extent display);

// The eye offsets kDefaultIpdMetres (math/pose.hpp) implies.
// The left eye: the head pose moved ipd/2 along its own -X (right) axis, same orientation.
Pose left_eye_pose(const Pose& head, double ipd_metres = kDefaultIpdMetres);

}  // namespace dhr
