// skip_bench: what the tracer's and the codec's skips save, per scene and camera bookmark, as JSON (never
// asserts). Embree backend (the CPU server); every number compares the default (skipping) path against the
// exhaustive one, whose output bits are identical (tests/stress/skip_equivalence_test.cpp):
//   rays      shadow rays traced vs exhaustive (one per surface pixel and light), by skip reason
//   bytes     datagram bytes per eye frame: default codec vs unskipped (uniform chunks off, 32-bit masks),
//             and each skip alone
//   time      trace wall time (best of --repeat) with and without skips
//   skip_bench [--scene PATH]... [--size WxH] [--repeat N] [--threads N] [--lights SPECS]
// Without --scene: default_room, and living_room and LightsPunctualLamp from ../shared/data when present.
// Scenes without a bookmark file get four cameras orbiting their bounds. docs/performance.md, "Skipped work".
#include "cli/exit_codes.hpp"
#include "cli/help_flag.hpp"
#include "scene/camera_bookmarks.hpp"
#include "scene/session_scene.hpp"
#include "codec/codec.hpp"
#include "json_writer.hpp"
#include "trace/visibility_tracer.hpp"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace dhr;
using namespace dhr::bench;

struct Options {
  std::vector<std::string> scenes;
  Extent eye{640, 360};
  int repeat = 3;
  uint32_t threads = 0;
  std::string lights;  // light specs replacing every scene's lights (scene/scene.hpp), e.g. range-limited ones
};

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--scene" && has_value) {
      o.scenes.push_back(argv[++i]);
    } else if (a == "--size" && has_value) {
      unsigned w = 0, h = 0;
      if (std::sscanf(argv[++i], "%ux%u", &w, &h) != 2 || w == 0 || h == 0 || w > 4000 || h > 4000) return false;
      o.eye = Extent{w, h};
    } else if (a == "--repeat" && has_value) {
      o.repeat = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--lights" && has_value) {
      o.lights = argv[++i];
    } else if (a == "--threads" && has_value) {
      o.threads = static_cast<uint32_t>(std::max(0, std::atoi(argv[++i])));
    } else {
      return false;
    }
  }
  if (o.scenes.empty()) {
    o.scenes.push_back(std::string(DHR_SOURCE_DIR) + "/" + kDefaultScenePath);
    const std::string data = DHR_SHARED_DATA_DIR;
    for (const char* rel : {"/scenes/living_room.glb", "/scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf"})
      if (std::filesystem::exists(data + rel)) o.scenes.push_back(data + rel);
  }
  return true;
}

struct NamedCamera {
  std::string name;
  Camera camera;
};

std::vector<NamedCamera> cameras_for(const std::string& path, const Scene& scene, Extent eye) {
  std::vector<NamedCamera> out;
  const GuardBand guard = paper_guard_band(eye);
  const Fov fov = symmetric_fov(90.0, eye);
  std::string error;
  const std::string bookmark_file = camera_bookmarks_path(path);
  if (std::filesystem::exists(bookmark_file)) {
    if (auto bookmarks = load_camera_bookmarks(bookmark_file, &error)) {
      for (const CameraBookmark& b : *bookmarks)
        out.push_back({b.name, Camera::with_guard_band(View{left_eye_pose(*look_at_pose(b)), fov}, eye,
                                                       guard)});
      return out;
    }
    std::fprintf(stderr, "skip_bench: %s\n", error.c_str());
  }
  const glm::dvec3 c(scene.bounds.center());
  const double r = std::max(0.5, double(scene.bounds.diagonal()));
  for (int i = 0; i < 4; ++i) {
    const double a = 0.6 + glm::two_pi<double>() * i / 4;
    CameraBookmark b;
    b.name = "orbit" + std::to_string(i);
    b.position = c + glm::dvec3(r * std::sin(a), 0.4 * r, r * std::cos(a));
    b.target = c;
    out.push_back({b.name, Camera::with_guard_band(View{*look_at_pose(b), fov}, eye, guard)});
  }
  return out;
}

size_t datagram_bytes(const VisibilityBuffer& v, const EncodeOptions& options) {
  std::vector<EncodedShard> shards;
  CodecStats stats;
  if (!encode_visibility(v, options, shards, &stats)) return 0;
  return stats.datagram_bytes;
}

struct Sums {
  uint64_t pixels = 0, surface = 0, shadow_rays = 0, exhaustive_rays = 0, backfacing = 0, out_of_range = 0,
           culled = 0;
  uint64_t bytes = 0, bytes_unskipped = 0, bytes_no_uniform = 0, bytes_wide = 0, raw_bytes = 0;
  double ms = 0.0, ms_exhaustive = 0.0;
};

// Best-of-N trace wall times of both tracers, interleaved so that load from other processes hits both alike;
// the buffers and stats of the last run.
void timed_traces(server::VisibilityTracer& fast, server::VisibilityTracer& full, const Camera& camera, int repeat,
                  VisibilityBuffer& out_fast, server::TraceStats& stats_fast, double& ms_fast,
                  VisibilityBuffer& out_full, server::TraceStats& stats_full, double& ms_full) {
  ms_fast = ms_full = std::numeric_limits<double>::infinity();
  for (int i = 0; i < repeat; ++i) {
    fast.trace(camera, out_fast, stats_fast);
    ms_fast = std::min(ms_fast, stats_fast.trace_ms);
    full.trace(camera, out_full, stats_full);
    ms_full = std::min(ms_full, stats_full.trace_ms);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  const char* const usage =
      "usage: skip_bench [--scene PATH]... [--size WxH] [--repeat N] [--threads N] [--lights SPECS]\n";
  if (cli::asks_for_help(argc, argv)) {
    std::fputs(usage, stdout);
    return exit_code::kOk;
  }
  if (!parse(argc, argv, o)) {
    std::fputs(usage, stderr);
    return exit_code::kUsage;
  }
  JsonWriter j;
  j.begin_object();
  j.value("bench", "skip_bench");
  j.value("build_type", DHR_BUILD_TYPE);
  j.begin_object("settings");
  j.value("eye_width", o.eye.width);
  j.value("eye_height", o.eye.height);
  j.value("repeat", o.repeat);
  j.value("backend", "embree");
  j.value("unskipped_codec", "uniform chunks off, 32-bit masks");
  j.value("lights", o.lights.empty() ? std::string("from the scene") : o.lights);
  j.end_object();
  j.begin_array("scenes");
  bool device_written = false;
  for (const std::string& path : o.scenes) {
    std::string load_error;
    std::optional<Scene> loaded = load_session_scene(path, o.lights, &load_error);
    if (!loaded) {
      std::fprintf(stderr, "skip_bench: %s\n", load_error.c_str());
      return exit_code::kUsage;
    }
    Scene& scene = *loaded;
    server::TracerOptions skipping, exhaustive;
    skipping.threads = exhaustive.threads = o.threads;
    exhaustive.skip = server::SkipOptions::none();
    auto fast = server::create_tracer(server::TracerBackend::kEmbree, scene, skipping);
    auto full = server::create_tracer(server::TracerBackend::kEmbree, scene, exhaustive);
    if (!device_written) {
      std::fprintf(stderr, "skip_bench: %s\n", fast->device_description().c_str());
      device_written = true;
    }
    EncodeOptions no_uniform;
    no_uniform.uniform_min_bytes = std::numeric_limits<size_t>::max();
    Sums sum;
    j.begin_object();
    j.value("scene", std::filesystem::path(path).filename().string());
    j.value("device", fast->device_description());
    j.value("triangles", static_cast<unsigned long long>(scene.triangle_count));
    j.value("lights", static_cast<unsigned>(scene.lights.size()));
    j.begin_array("cameras");
    for (const NamedCamera& nc : cameras_for(path, scene, o.eye)) {
      VisibilityBuffer a, b;
      server::TraceStats sa, sb;
      double ms = 0.0, ms_full = 0.0;
      timed_traces(*fast, *full, nc.camera, o.repeat, a, sa, ms, b, sb, ms_full);
      const bool identical = a == b;
      const VisibilityBuffer wide = a.with_mask_width(MaskWidth::k32);
      const size_t bytes = datagram_bytes(a, EncodeOptions{}), bytes_no_uniform = datagram_bytes(a, no_uniform),
                   bytes_wide = datagram_bytes(wide, EncodeOptions{}), bytes_unskipped = datagram_bytes(wide, no_uniform);
      j.begin_object();
      j.value("camera", nc.name);
      j.value("identical_bits", identical);
      j.value("pixels", static_cast<unsigned long long>(sa.pixels));
      j.value("surface_pixels", static_cast<unsigned long long>(sa.pixels - sa.background_pixels));
      j.value("shadow_rays", static_cast<unsigned long long>(sa.shadow_rays));
      j.value("shadow_rays_exhaustive", static_cast<unsigned long long>(sb.shadow_rays));
      j.value("skipped_backfacing", static_cast<unsigned long long>(sa.skipped_backfacing));
      j.value("skipped_out_of_range", static_cast<unsigned long long>(sa.skipped_out_of_range));
      j.value("skipped_culled_light", static_cast<unsigned long long>(sa.skipped_culled_light));
      j.value("lights_culled", sa.lights_culled);
      j.value("bytes", static_cast<unsigned long long>(bytes));
      j.value("bytes_unskipped", static_cast<unsigned long long>(bytes_unskipped));
      j.value("bytes_without_uniform_chunks", static_cast<unsigned long long>(bytes_no_uniform));
      j.value("bytes_with_32bit_masks", static_cast<unsigned long long>(bytes_wide));
      j.value("trace_ms", ms);
      j.value("trace_ms_exhaustive", ms_full);
      j.end_object();
      sum.pixels += sa.pixels;
      sum.surface += sa.pixels - sa.background_pixels;
      sum.shadow_rays += sa.shadow_rays;
      sum.exhaustive_rays += sb.shadow_rays;
      sum.backfacing += sa.skipped_backfacing;
      sum.out_of_range += sa.skipped_out_of_range;
      sum.culled += sa.skipped_culled_light;
      sum.bytes += bytes;
      sum.bytes_unskipped += bytes_unskipped;
      sum.bytes_no_uniform += bytes_no_uniform;
      sum.bytes_wide += bytes_wide;
      sum.raw_bytes += a.size_bytes();
      sum.ms += ms;
      sum.ms_exhaustive += ms_full;
    }
    j.end_array();
    j.begin_object("total");
    j.value("shadow_rays", static_cast<unsigned long long>(sum.shadow_rays));
    j.value("shadow_rays_exhaustive", static_cast<unsigned long long>(sum.exhaustive_rays));
    j.value("rays_saved_fraction",
            sum.exhaustive_rays ? 1.0 - double(sum.shadow_rays) / double(sum.exhaustive_rays) : 0.0, 4);
    j.value("skipped_backfacing", static_cast<unsigned long long>(sum.backfacing));
    j.value("skipped_out_of_range", static_cast<unsigned long long>(sum.out_of_range));
    j.value("skipped_culled_light", static_cast<unsigned long long>(sum.culled));
    j.value("bytes", static_cast<unsigned long long>(sum.bytes));
    j.value("bytes_unskipped", static_cast<unsigned long long>(sum.bytes_unskipped));
    j.value("bytes_without_uniform_chunks", static_cast<unsigned long long>(sum.bytes_no_uniform));
    j.value("bytes_with_32bit_masks", static_cast<unsigned long long>(sum.bytes_wide));
    j.value("bytes_saved_fraction",
            sum.bytes_unskipped ? 1.0 - double(sum.bytes) / double(sum.bytes_unskipped) : 0.0, 4);
    j.value("trace_ms", sum.ms);
    j.value("trace_ms_exhaustive", sum.ms_exhaustive);
    j.value("time_saved_fraction", sum.ms_exhaustive > 0.0 ? 1.0 - sum.ms / sum.ms_exhaustive : 0.0, 4);
    j.end_object();
    j.end_object();
  }
  j.end_array();
  j.end_object();
  std::printf("%s\n", j.str().c_str());
  return 0;
}
