// motion_bench: what moving the Embree scene to a scene time costs (EmbreeScene::set_scene_time) against a full
// rebuild (EmbreeScene::create of scene_at(scene, t), the flattened scene at t); one JSON line, never asserts.
//   motion_bench [--scene PATH] [--threads N] [--builds N] [--updates N] [--size WxH] [--vulkan]
// Defaults: ../shared/data/scenes/living_room_moving.glb, all cores, 5 builds, 41 updates at times spread over the
// longest animation (each a different pose), 1280x1440 per eye for the trace times. Reports:
//   full_build_ms       median create() of the flattened scene at t (what an update replaces)
//   motion_build_ms     median create() of the animated scene (dynamic; once per session)
//   update_ms           median (and max) set_scene_time over the updates; ratio = update_ms / full_build_ms
//   moving_meshes / moving_vertices, moved_meshes_mean / moved_vertices_mean (per update: meshes whose pose changed)
//   trace_ms_flat / trace_ms_motion   one eye of each bookmark (sum, median of 3), flattened vs dynamic, at the
//                                     same time: what the dynamic (two-level) BVH costs the tracer
//   vulkan (with --vulkan)  the Vulkan backend on its device (lavapipe here): full_build_ms (a VulkanTracer of the
//                           flattened scene at t: every BLAS and the TLAS), update_ms (set_scene_time: moved
//                           instances' transforms, one TLAS update, their shading vertices), ratio
// docs/server.md ("Motion") has the measured numbers and the command.
#include "bench_timing.hpp"
#include "bench_views.hpp"
#include "cli/exit_codes.hpp"
#include "cli/help_flag.hpp"
#include "scene/scene_at.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "trace/vulkan/vulkan_tracer.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace dhr;
using namespace dhr::bench;

constexpr const char* kUsageText =
    "usage: motion_bench [--scene PATH] [--threads N] [--builds N] [--updates N] [--size WxH] [--vulkan]\n";

int usage() {
  std::fputs(kUsageText, stderr);
  return exit_code::kUsage;
}

double trace_ms(server::EmbreeTracer& tracer, const std::vector<Camera>& cameras) {
  std::vector<double> runs;
  for (int r = 0; r < 3; ++r) {
    double sum = 0.0;
    for (const Camera& c : cameras) {
      VisibilityBuffer out;
      server::TraceStats stats;
      tracer.trace(c, out, stats);
      sum += stats.trace_ms;
    }
    runs.push_back(sum);
  }
  return median(runs, 0.0);
}

// The Vulkan backend's full build of the flattened scene against its scene-time update.
nlohmann::json vulkan_motion(const Scene& scene, const std::vector<double>& times, uint32_t builds) {
  server::TracerOptions options;
  std::vector<double> full;
  for (uint32_t b = 0; b < builds; ++b)
    full.push_back(server::VulkanTracer(scene_at(scene, times[b % times.size()]), options).accel_stats().build_ms);
  server::VulkanTracer tracer(scene, options);
  std::vector<double> update_ms;
  for (double t : times) {
    tracer.set_scene_time(t);
    update_ms.push_back(tracer.last_motion_update_ms());
  }
  const double full_ms = median(full, 0.0), update = median(update_ms, 0.0);
  return {{"device", tracer.device_description()},
          {"full_build_ms", full_ms},
          {"update_ms", update},
          {"update_ms_max", *std::max_element(update_ms.begin(), update_ms.end())},
          {"ratio", full_ms > 0.0 ? update / full_ms : 0.0}};
}

}  // namespace

int main(int argc, char** argv) {
  std::string path = std::string(DHR_SHARED_DATA_DIR) + "/scenes/living_room_moving.glb";
  uint32_t threads = 0, builds = 5, updates = 41;
  Extent eye{1280, 1440};
  bool vulkan = false;
  if (cli::asks_for_help(argc, argv)) {
    std::fputs(kUsageText, stdout);
    return exit_code::kOk;
  }
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--scene") && has_value) path = argv[++i];
    else if (!std::strcmp(argv[i], "--threads") && has_value) threads = static_cast<uint32_t>(std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--builds") && has_value) builds = static_cast<uint32_t>(std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--updates") && has_value) updates = static_cast<uint32_t>(std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--vulkan")) vulkan = true;
    else if (!std::strcmp(argv[i], "--size") && has_value) {
      if (std::sscanf(argv[++i], "%ux%u", &eye.width, &eye.height) != 2) return usage();
    } else return usage();
  }
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  if (builds == 0 || updates == 0) return usage();

  SceneLoadResult loaded = load_scene(path);
  if (!loaded) {
    std::fprintf(stderr, "motion_bench: %s\n", loaded.error.c_str());
    return 1;
  }
  const Scene& scene = *loaded.scene;
  double duration = 0.0;
  for (const AnimationClip& c : scene.animation.clips) duration = std::max(duration, c.duration);
  server::EmbreeBuildOptions build;
  build.threads = threads;

  // Times spread over the loop (never repeating a pose, so every update moves every moving mesh).
  std::vector<double> times;
  for (uint32_t i = 0; i < updates; ++i) times.push_back(duration * (0.013 + 0.97 * i / updates));
  const double probe_t = times[times.size() / 2];

  std::vector<double> full, motion;
  for (uint32_t b = 0; b < builds; ++b) {
    const Scene at = scene_at(scene, times[b % times.size()]);
    full.push_back(server::EmbreeScene::create(at, build)->stats().build_ms);
    motion.push_back(server::EmbreeScene::create(scene, build)->stats().build_ms);
  }
  std::unique_ptr<server::EmbreeScene> es = server::EmbreeScene::create(scene, build);
  std::vector<double> update_ms;
  double moved_meshes_sum = 0.0, moved_vertices_sum = 0.0;
  for (double t : times) {
    es->set_scene_time(scene, t);
    update_ms.push_back(es->motion_stats().last_update_ms);
    moved_meshes_sum += es->motion_stats().moved_meshes;
    moved_vertices_sum += static_cast<double>(es->motion_stats().moved_vertices);
  }
  const server::MotionStats& ms = es->motion_stats();

  // Trace times at probe_t: the flattened scene at t against the dynamic scene moved to t.
  std::string note;
  std::vector<Camera> cameras;
  for (const CameraBookmark& b : bench_bookmarks(path, scene, note))
    if (auto c = bench_eye_camera(b, 0, eye)) cameras.push_back(*c);
  server::TracerOptions options;
  options.threads = threads;
  server::EmbreeTracer flat(scene_at(scene, probe_t), options);
  server::EmbreeTracer moving(scene, options);
  moving.set_scene_time(probe_t);

  nlohmann::json j;
  j["record"] = "motion";
  j["scene"] = path;
  j["threads"] = threads;
  j["build_type"] = DHR_BUILD_TYPE;
  j["duration_s"] = duration;
  j["meshes"] = scene.meshes.size();
  j["triangles"] = scene.triangle_count;
  j["dynamic"] = es->is_dynamic();
  j["moving_meshes"] = ms.moving_meshes;
  j["moving_vertices"] = ms.moving_vertices;
  j["moved_meshes_mean"] = moved_meshes_sum / updates;
  j["moved_vertices_mean"] = moved_vertices_sum / updates;
  j["builds"] = builds;
  j["updates"] = updates;
  j["full_build_ms"] = median(full, 0.0);
  j["motion_build_ms"] = median(motion, 0.0);
  j["update_ms"] = median(update_ms, 0.0);
  j["update_ms_max"] = *std::max_element(update_ms.begin(), update_ms.end());
  j["ratio"] = median(full, 0.0) > 0.0 ? median(update_ms, 0.0) / median(full, 0.0) : 0.0;
  j["views"] = cameras.size();
  j["eye"] = std::to_string(eye.width) + "x" + std::to_string(eye.height);
  j["trace_ms_flat"] = trace_ms(flat, cameras);
  j["trace_ms_motion"] = trace_ms(moving, cameras);
  if (vulkan) {
    try {
      j["vulkan"] = vulkan_motion(scene, times, builds);
    } catch (const std::exception& e) {
      j["vulkan"] = {{"error", e.what()}};
    }
  }
  std::printf("%s\n", j.dump().c_str());
  return 0;
}
