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

void split_guard_band(Extent traced, Extent& out_display, GuardBand& out_guard) {
  // The display size gets the traced size's parity, so the guard band is whole pixels on each side and
  // display + 2 * guard is exactly the traced size.
  auto display = [](uint32_t t, uint32_t display_ref, uint32_t traced_ref) {
    const uint64_t d = (uint64_t{t} * display_ref + traced_ref / 2) / traced_ref;
    return static_cast<uint32_t>(d < 2 ? t : d - (t - d) % 2);
  };
  out_display = {display(traced.width, 1920, 1984), display(traced.height, 1080, 1116)};
  out_guard = {(traced.width - out_display.width) / 2, (traced.height - out_display.height) / 2};
}


std::optional<Camera> bench_eye_camera(const CameraBookmark& bookmark, int eye, Extent display) {
  const std::optional<Pose> head = look_at_pose(bookmark);
  if (!head) return std::nullopt;
  // left_eye_pose moves by -ipd/2 along the head's x axis: a negative IPD gives the right eye.
  const double ipd = eye == 0 ? kDefaultIpdMetres : -kDefaultIpdMetres;
  const View view{left_eye_pose(*head, ipd), symmetric_fov(kTraceBenchFovDegrees, display)};
  return Camera::with_guard_band(view, display, bench_guard_band(display));
}

}  // namespace dhr::bench
