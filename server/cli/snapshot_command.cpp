#include "snapshot_command.hpp"

#include "scene/camera_bookmarks.hpp"
#include "image/png_writer.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "preview_shading.hpp"
#include "cli/exit_codes.hpp"
#include "scene_setup.hpp"
#include "trace/stats_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace dhr::server::cli {
std::string file_safe_name(const std::string& name) {
  std::string out;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    out.push_back(ok ? c : '_');
  }
  return out.empty() ? "camera" : out;
}

int run_snapshot(const ServerOptions& options) {
  std::string error;
  std::optional<Scene> scene = load_server_scene(options, &error);
  if (!scene) return fail_setup(error);

  std::vector<CameraBookmark> bookmarks;
  if (!options.cameras.empty()) {
    for (size_t i = 0; i < options.cameras.size(); ++i) {
      auto b = parse_camera_spec(options.cameras[i], &error);
      if (!b) return fail_setup("--camera: " + error);
      b->name = "camera" + std::to_string(i);
      bookmarks.push_back(*b);
    }
  } else {
    const std::string path = camera_bookmarks_path(options.scene_path);
    auto loaded = load_camera_bookmarks(path, &error);
    if (!loaded) return fail_setup(error + " (give cameras with --camera x,y,z:tx,ty,tz)");
    bookmarks = std::move(*loaded);
  }

  std::error_code ec;
  std::filesystem::create_directories(options.snapshot_dir, ec);
  if (ec || !std::filesystem::is_directory(options.snapshot_dir))
    return fail_run(options.snapshot_dir + ": cannot create the output directory");

  std::unique_ptr<VisibilityTracer> tracer;
  try {
    tracer = create_tracer(options.backend, *scene, options.tracer);
  } catch (const std::exception& e) {
    return fail_run(std::string("cannot create the tracer: ") + e.what());
  }
  // The preview's primary rays come from Embree; reuse the tracer's scene when it is Embree.
  std::unique_ptr<EmbreeScene> own_preview_scene;
  const EmbreeScene* preview_scene = nullptr;
  if (const auto* et = dynamic_cast<const EmbreeTracer*>(tracer.get())) {
    preview_scene = &et->embree_scene();
  } else {
    own_preview_scene = EmbreeScene::create(*scene);
    preview_scene = own_preview_scene.get();
  }

  const GuardBand guard = effective_guard_band(options);
  const Fov fov = symmetric_fov(options.fov_deg, options.eye_size);
  std::vector<std::string> used_names;
  for (const CameraBookmark& bookmark : bookmarks) {
    const std::optional<Pose> head = look_at_pose(bookmark);
    if (!head) return fail_setup("camera '" + bookmark.name + "': cannot look from its position at its target");
    const View view{left_eye_pose(*head), fov};
    const Camera camera = Camera::with_guard_band(view, options.eye_size, guard);

    VisibilityBuffer visibility;
    TraceStats stats;
    std::vector<double> times;
    try {
      for (uint32_t r = 0; r < options.repeat; ++r) {
        tracer->trace(camera, visibility, stats);
        times.push_back(stats.trace_ms);
      }
    } catch (const std::exception& e) {
      return fail_run("camera '" + bookmark.name + "': " + e.what());
    }
    std::sort(times.begin(), times.end());
    stats.trace_ms = times[times.size() / 2];

    // Unique file names even when two bookmarks sanitize to the same text.
    std::string base = file_safe_name(bookmark.name);
    while (std::find(used_names.begin(), used_names.end(), base) != used_names.end()) base += "_";
    used_names.push_back(base);

    const uint32_t w = camera.extent.width, h = camera.extent.height;
    nlohmann::ordered_json files = nlohmann::ordered_json::array();
    std::vector<uint8_t> grey(static_cast<size_t>(w) * h);
    for (uint32_t li = 0; li < tracer->light_count(); ++li) {
      for (size_t i = 0; i < grey.size(); ++i) grey[i] = (visibility.mask_at(i) >> li & 1u) ? 255 : 0;
      const std::string path = (std::filesystem::path(options.snapshot_dir) / (base + "_light" + std::to_string(li) + ".png")).string();
      if (const auto err = write_png(path, w, h, 1, grey)) return fail_run(*err);
      files.push_back(path);
    }
    const std::string shaded = (std::filesystem::path(options.snapshot_dir) / (base + "_shaded.png")).string();
    if (const auto err = write_png(shaded, w, h, 3, shade_preview(*scene, *preview_scene, camera, visibility)))
      return fail_run(*err);
    files.push_back(shaded);

    nlohmann::ordered_json stats_json = to_json(stats);
    stats_json["trace_ms_min"] = times.front();
    stats_json["trace_ms_max"] = times.back();
    stats_json["repeat"] = options.repeat;
    const nlohmann::ordered_json report = {
        {"bookmark", bookmark.name},
        {"scene", scene->source},
        {"backend", tracer_backend_name(tracer->backend())},
        {"device", tracer->device_description()},
        {"eye_size", {options.eye_size.width, options.eye_size.height}},
        {"guard", {2 * guard.x, 2 * guard.y}},  // both sides together, as --guard
        {"extent", {w, h}},
        {"fov_deg", options.fov_deg},
        {"lights", tracer->light_count()},
        {"mask_bits", static_cast<int>(visibility.mask_bits)},
        {"skip", to_json(options.tracer.skip)},
        {"accel", to_json(tracer->accel_stats())},
        {"stats", stats_json},
        {"files", files}};
    std::printf("%s\n", report.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace).c_str());
    std::fflush(stdout);
  }
  return exit_code::kOk;
}

}  // namespace dhr::server::cli
