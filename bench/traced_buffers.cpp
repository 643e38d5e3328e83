#include "traced_buffers.hpp"

#include "scene/camera_bookmarks.hpp"
#include "scene/scene.hpp"
#include "trace/visibility_tracer.hpp"

#include <chrono>
#include <exception>
#include <memory>

namespace dhr::bench {

bool trace_bookmark_buffers(const std::string& scene_path, Extent traced, unsigned threads, BufferSet& out,
                            std::string* out_error) {
  try {
    const SceneLoadResult loaded = load_scene(scene_path);
    if (!loaded) {
      *out_error = loaded.error;
      return false;
    }
    const auto bookmarks = load_camera_bookmarks(camera_bookmarks_path(scene_path), out_error);
    if (!bookmarks) return false;
    server::TracerOptions options;
    options.threads = threads;
    const auto tracer = server::create_tracer(server::TracerBackend::kEmbree, *loaded.scene, options);
    Extent display;
    GuardBand guard;
    split_guard_band(traced, display, guard);
    out.name = "traced";
    out.source = scene_path + " (" + std::to_string(bookmarks->size()) + " camera bookmarks, both eyes)";
    out.tracer = tracer->device_description();
    double trace_ms = 0.0;
    for (const CameraBookmark& b : *bookmarks) {
      const auto head = look_at_pose(b);
      if (!head) continue;
      Pose right = *head;
      right.position = head->transform_point(glm::dvec3(0.5 * kDefaultIpdMetres, 0.0, 0.0));
      const Pose eyes[2] = {left_eye_pose(*head), right};
      const char* names[2] = {"left", "right"};
      for (int e = 0; e < 2; ++e) {
        const View view{eyes[e], symmetric_fov(kBenchFovDegrees, display)};
        VisibilityBuffer vis;
        server::TraceStats stats;
        const auto start = std::chrono::steady_clock::now();
        tracer->trace(Camera::with_guard_band(view, display, guard), vis, stats);
        trace_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        out.labels.push_back(b.name + "/" + names[e]);
        out.buffers.push_back(std::move(vis));
      }
    }
    if (out.buffers.empty()) {
      *out_error = scene_path + ": no usable camera bookmark";
      return false;
    }
    out.trace_ms_mean = trace_ms / static_cast<double>(out.buffers.size());
    return true;
  } catch (const std::exception& e) {
    *out_error = e.what();
    return false;
  }
}

}  // namespace dhr::bench
