#include "app/start_pose.hpp"

#include <optional>
#include <vector>

#include "app/run_modes.hpp"
#include "scene/camera_bookmarks.hpp"

namespace dhr::client {

namespace {

CameraBookmark pick_bookmark(const std::string& which, const std::string& scene_path) {
  const std::string path = camera_bookmarks_path(scene_path);
  std::string error;
  const std::optional<std::vector<CameraBookmark>> bookmarks = load_camera_bookmarks(path, &error);
  if (!bookmarks) throw InputError("--start-at: " + error);
  if (which.empty()) return bookmarks->front();
  for (const CameraBookmark& b : *bookmarks) {
    if (b.name == which) return b;
  }
  if (which.find_first_not_of("0123456789") == std::string::npos && which.size() < 6) {
    const size_t index = std::stoul(which);
    if (index < bookmarks->size()) return (*bookmarks)[index];
  }
  throw InputError("--start-at: " + path + " has no bookmark '" + which + "' (" + std::to_string(bookmarks->size()) +
                   " bookmarks)");
}

}  // namespace

Pose resolve_start_pose(const std::string& spec, const std::string& scene_path) {
  CameraBookmark bookmark;
  if (spec == "bookmark") {
    bookmark = pick_bookmark("", scene_path);
  } else if (spec.rfind("bookmark:", 0) == 0) {
    if (spec.size() == 9) throw InputError("--start-at: 'bookmark:' names no bookmark (bookmark:N or bookmark:NAME)");
    bookmark = pick_bookmark(spec.substr(9), scene_path);
  } else {
    std::string error;
    const std::optional<CameraBookmark> parsed = parse_camera_spec(spec, &error);
    if (!parsed) throw InputError("--start-at: " + error + " (expected bookmark, bookmark:N or x,y,z:tx,ty,tz)");
    bookmark = *parsed;
  }
  const std::optional<Pose> pose = look_at_pose(bookmark);
  if (!pose) throw InputError("--start-at: the camera '" + spec + "' looks straight up or down");
  return *pose;
}

}  // namespace dhr::client
