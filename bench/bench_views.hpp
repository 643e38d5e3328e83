// Scenes, cameras and eye views for bench/trace_bench.
#pragma once
#include "scene/camera_bookmarks.hpp"
#include "math/projection.hpp"
#include "scene/scene.hpp"

#include <string>
#include <vector>

namespace dhr::bench {

// The scenes measured by default, in order, those that exist: living_room (headline), living_room_dense and
// LightsPunctualLamp from ../shared/data/scenes, then the project's assets/scenes/default_room.gltf.
std::vector<std::string> default_trace_scenes(const std::string& shared_data_dir, const std::string& source_dir);

// The scene's "<scene>.cameras.json" bookmarks; for a scene without one, a single bookmark "bbox_front"
// (in front of the bounding box (+Z) and a little above, looking at its centre from where its bounding
// sphere just fits the view; `note` says so).
// Throws std::runtime_error with a one-line reason for a malformed bookmark file.
std::vector<CameraBookmark> bench_bookmarks(const std::string& scene_path, const Scene& scene,
                                                    std::string& note);

inline constexpr double kTraceBenchFovDegrees = 90.0;  // horizontal, of the displayed region

// Guard band of a display size: the server's default, 64x36 at 1920x1080, scaled.
GuardBand bench_guard_band(Extent display);

// The displayed size and guard band for a traced (guard-banded) buffer size, in the paper's proportion
// (1920x1080 displayed + 64x36 guard = 1984x1116).
void split_guard_band(Extent traced, Extent& out_display, GuardBand& out_guard);

// The guard-banded camera of one eye (0 left, 1 right; IPD 63 mm) of a bookmark, or std::nullopt when the
// bookmark has no usable look-at pose.
std::optional<Camera> bench_eye_camera(const CameraBookmark& bookmark, int eye, Extent display);

}  // namespace dhr::bench
