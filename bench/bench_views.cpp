#include "bench_views.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace dhr::bench {

std::vector<std::string> default_trace_scenes(const std::string& shared_data_dir, const std::string& source_dir) {
  const std::string candidates[] = {
      shared_data_dir + "/scenes/living_room.glb",
      shared_data_dir + "/scenes/living_room_dense.glb",
      shared_data_dir + "/scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf",
      source_dir + "/assets/scenes/default_room.gltf",
  };
  std::vector<std::string> out;
  for (const std::string& c : candidates)
    if (std::filesystem::exists(c)) out.push_back(c);
  return out;
}

std::vector<CameraBookmark> bench_bookmarks(const std::string& scene_path, const Scene& scene,
                                                    std::string& note) {
  const std::string path = camera_bookmarks_path(scene_path);
  if (std::filesystem::exists(path)) {
    std::string error;
    auto loaded = load_camera_bookmarks(path, &error);
    if (!loaded) throw std::runtime_error(error);
    note = path;
    return *loaded;
  }
  note = "no " + path + ": one camera in front of the bounding box";
  return {front_bookmark(scene.bounds)};
}

GuardBand bench_guard_band(Extent display) { return paper_guard_band(display); }

std::optional<Camera> bench_eye_camera(const CameraBookmark& bookmark, int eye, Extent display) {
  const std::optional<Pose> head = look_at_pose(bookmark);
  if (!head) return std::nullopt;
  // left_eye_pose moves by -ipd/2 along the head's x axis: a negative IPD gives the right eye.
  const double ipd = eye == 0 ? kDefaultIpdMetres : -kDefaultIpdMetres;
  const View view{left_eye_pose(*head, ipd), symmetric_fov(kTraceBenchFovDegrees, display)};
  return Camera::with_guard_band(view, display, bench_guard_band(display));
}

}  // namespace dhr::bench
