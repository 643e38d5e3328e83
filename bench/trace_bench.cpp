// trace_bench: the server's visibility tracer on real scenes; one JSON object per line, never asserts.
//   trace_bench [--scene PATH]... [--sizes WxH,WxH...] [--repeat N] [--bookmarks N] [--threads N]
//               [--vulkan-size WxH] [--no-vulkan] [--no-bare] [--quick] [--soft-levels] [--lights N]
//               [--light-range M]
//   trace_bench --trace PATH ... : the sequence mode, with and without reuse (trace_sequence.hpp)
// Every scene is traced from each camera bookmark (both eyes, IPD 63 mm, 90 degree horizontal FOV plus
// the server's default guard band) at each size, by Embree with skipping on and with SkipOptions::none(),
// then its skipping-on rays are replayed by a bare rtcIntersect1 + rtcOccluded1 loop (bare_embree.hpp),
// and the Vulkan backend traces it on lavapipe at a small size. --soft-levels: every tracer traces in the scene's
// soft layout (trace_layout: each light with an extent sampled into its level field, as a session granted soft
// levels is traced) instead of one bit per light; no bare loop then. --lights N adds bench lights up to N (at most
// 256; bench_lights.hpp): beyond 32 the lights share slots (scene/light_slots.hpp; no bare loop then). Records, by
// their "record" field:
//   run      machine, build and settings
//   accel    one per tracer built: backend, device, driver, triangles, lights, scene load and AS build ms, bytes
//   light_slots  with more than 32 lights: the slots they share
//   trace    one per scene, backend, size, skip setting, bookmark and eye: statistics of the median trace,
//            trace ms (median, min of --repeat), Mrays/s (primary + shadow rays / median trace time)
//   bare     one per scene, size, bookmark and eye: the bare loop's ms and Mrays/s vs the tracer's
//   summary  one per scene, backend, size and skip setting (and bare loop): totals over bookmarks and eyes
//   error    what could not be measured, with a one-line reason
// docs/performance.md ("Server tracing") has the measured numbers and the commands.
#include "bare_embree.hpp"
#include "cli/exit_codes.hpp"
#include "cli/help_flag.hpp"
#include "bench_views.hpp"
#include "bench_lights.hpp"
#include "trace_bench_options.hpp"
#include "trace_sequence.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "trace/stats_json.hpp"
#include "trace/visibility_tracer.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace dhr;
using namespace dhr::bench;
using Json = nlohmann::ordered_json;

double round3(double v) { return std::round(v * 1000.0) / 1000.0; }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

double mrays_per_s(uint64_t rays, double ms) { return ms > 0.0 ? round3(static_cast<double>(rays) / ms / 1000.0) : 0.0; }

// (rays_a / ms_a) / (rays_b / ms_b); 0 when undefined.
double rate_ratio(uint64_t rays_a, double ms_a, uint64_t rays_b, double ms_b) {
  if (!(ms_a > 0.0) || !(ms_b > 0.0) || rays_b == 0) return 0.0;
  return (static_cast<double>(rays_a) / ms_a) / (static_cast<double>(rays_b) / ms_b);
}

void emit(const Json& j) {
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    const size_t colon = line.find(':');
    if (line.rfind("model name", 0) == 0 && colon != std::string::npos && colon + 2 <= line.size())
      return line.substr(colon + 2);
  }
  return "unknown";
}

std::string size_text(Extent e) { return std::to_string(e.width) + "x" + std::to_string(e.height); }

struct LoadedScene {
  std::string path;
  Scene scene;
  double load_ms = 0.0;
  std::vector<CameraBookmark> bookmarks;
  std::string bookmark_source;
};

Json base_record(const char* record, const LoadedScene& s) {
  return Json{{"record", record}, {"scene", s.path}};
}

Json size_json(Extent display) {
  const GuardBand g = bench_guard_band(display);
  const TracedFormat format{display, g};
  return Json{{"display", size_text(display)},
              {"guard", size_text(Extent{2 * g.x, 2 * g.y})},  // both sides together, as before
              {"traced", size_text(format.buffer())}};
}

// Totals over bookmarks and eyes for one summary record.
struct Totals {
  uint64_t rays = 0, shadow_rays = 0, skipped = 0;
  double ms = 0.0, cpu_ms = 0.0;
  size_t eyes = 0;
  void add(const server::TraceStats& s, double trace_ms, double trace_cpu_ms) {
    rays += s.primary_rays + s.shadow_rays;
    shadow_rays += s.shadow_rays;
    skipped += s.skipped_backfacing + s.skipped_out_of_range + s.skipped_culled_light;
    ms += trace_ms;
    cpu_ms += trace_cpu_ms;
    ++eyes;
  }
};

// One eye's median trace: its statistics, wall and process CPU ms.
struct EyeResult {
  server::TraceStats stats;
  double ms = 0.0;
  double cpu_ms = 0.0;
};

std::string driver_text(const server::VisibilityTracer& tracer) {
  return tracer.backend() == server::TracerBackend::kEmbree ? std::string("Embree ") + RTC_VERSION_STRING
                                                            : tracer.device_description();
}

std::unique_ptr<server::VisibilityTracer> build_tracer(server::TracerBackend backend, const LoadedScene& s,
                                                       const server::TracerOptions& options) {
  auto tracer = server::create_tracer(backend, s.scene, options);
  Json j = base_record("accel", s);
  j["backend"] = server::tracer_backend_name(backend);
  j["device"] = tracer->device_description();
  j["driver"] = driver_text(*tracer);
  j["skip"] = server::to_json(options.skip);
  j["triangles"] = s.scene.triangle_count;
  j["lights"] = tracer->light_count();
  j["load_ms"] = round3(s.load_ms);
  j["accel"] = server::to_json(tracer->accel_stats());
  emit(j);
  return tracer;
}

// Traces every bookmark and eye `repeat` times; one trace record each and a summary. Returns per eye the
// median trace (in bookmark, eye order) for the bare-loop comparison.
std::vector<EyeResult> trace_views(server::VisibilityTracer& tracer, const LoadedScene& s,
                                                               Extent display, const server::SkipOptions& skip,
                                                               const TraceBenchOptions& o) {
  std::vector<EyeResult> per_eye;
  Totals totals;
  VisibilityBuffer vis;
  bool warmed = false;
  const VisibilityLayout layout = o.soft_levels
                                      ? server::layout_for_lights(tracer.light_extents(), tracer.light_count())
                                      : VisibilityLayout::hard(tracer.light_count());
  auto trace = [&](const Camera& camera, server::TraceStats& stats) {
    if (o.soft_levels) {
      tracer.trace_layout(camera, layout, vis, stats);
    } else {
      tracer.trace(camera, vis, stats);
    }
  };
  for (const CameraBookmark& b : s.bookmarks) {
    for (int eye = 0; eye < 2; ++eye) {
      const std::optional<Camera> camera = bench_eye_camera(b, eye, display);
      if (!camera) continue;
      server::TraceStats stats;
      if (!warmed) trace(*camera, stats);  // first touch of buffers and caches: untimed
      warmed = true;
      std::vector<double> times, gpu_times, cpu_times;
      std::vector<server::TraceStats> all;
      for (int r = 0; r < o.repeat; ++r) {
        const double cpu0 = process_cpu_ms();
        trace(*camera, stats);
        cpu_times.push_back(process_cpu_ms() - cpu0);
        times.push_back(stats.trace_ms);
        gpu_times.push_back(stats.gpu_ms);
        all.push_back(stats);
      }
      const double med = median(times);
      // The statistics of the trace closest to the median (counts are the same in every repetition).
      size_t pick = 0;
      for (size_t i = 1; i < times.size(); ++i)
        if (std::fabs(times[i] - med) < std::fabs(times[pick] - med)) pick = i;
      const server::TraceStats& st = all[pick];
      Json j = base_record("trace", s);
      j["backend"] = server::tracer_backend_name(tracer.backend());
      j["device"] = tracer.device_description();
      j["driver"] = driver_text(tracer);
      j["triangles"] = s.scene.triangle_count;
      j["accel_build_ms"] = round3(tracer.accel_stats().build_ms);
      j["bookmark"] = b.name;
      j["eye"] = eye == 0 ? "left" : "right";
      j["resolution"] = size_json(display);
      j["lights"] = tracer.light_count();
      j["settings"] = Json{{"skip", server::to_json(skip)}, {"repeat", o.repeat}, {"fov_deg", kTraceBenchFovDegrees},
                           {"soft_levels", o.soft_levels}, {"mask_bits", layout.total_bits()}};
      j["stats"] = server::to_json(st);
      j["trace_ms"] = Json{{"median", round3(med)}, {"min", round3(*std::min_element(times.begin(), times.end()))}};
      if (st.gpu_ms >= 0.0) j["gpu_ms_median"] = round3(median(gpu_times));
      const double cpu_med = median(cpu_times);
      j["cpu_ms_median"] = round3(cpu_med);
      j["rays"] = st.primary_rays + st.shadow_rays;
      j["mrays_s"] = mrays_per_s(st.primary_rays + st.shadow_rays, med);
      j["mrays_per_cpu_s"] = mrays_per_s(st.primary_rays + st.shadow_rays, cpu_med);
      emit(j);
      totals.add(st, med, cpu_med);
      per_eye.push_back({st, med, cpu_med});
    }
  }
  Json j = base_record("summary", s);
  j["kind"] = "tracer";
  j["backend"] = server::tracer_backend_name(tracer.backend());
  j["device"] = tracer.device_description();
  j["resolution"] = size_json(display);
  j["skip"] = server::to_json(skip);
  j["soft_levels"] = o.soft_levels;
  j["eyes"] = totals.eyes;
  j["trace_ms_per_eye_mean"] = totals.eyes ? round3(totals.ms / static_cast<double>(totals.eyes)) : 0.0;
  j["rays_per_eye_mean"] = totals.eyes ? totals.rays / totals.eyes : 0;
  j["shadow_rays_per_eye_mean"] = totals.eyes ? totals.shadow_rays / totals.eyes : 0;
  j["skipped_pairs_per_eye_mean"] = totals.eyes ? totals.skipped / totals.eyes : 0;
  j["cpu_ms_per_eye_mean"] = totals.eyes ? round3(totals.cpu_ms / static_cast<double>(totals.eyes)) : 0.0;
  j["mrays_s"] = mrays_per_s(totals.rays, totals.ms);
  j["mrays_per_cpu_s"] = mrays_per_s(totals.rays, totals.cpu_ms);
  emit(j);
  return per_eye;
}

// The bare loop over each eye's skipping-on rays, against the tracer's median trace of the same view.
void bare_views(const server::EmbreeTracer& tracer, const LoadedScene& s, Extent display,
                const std::vector<EyeResult>& tracer_eyes, unsigned threads,
                const TraceBenchOptions& o) {
  const RTCScene handle = tracer.embree_scene().handle();
  uint64_t tracer_rays = 0, bare_rays = 0;
  double tracer_ms = 0.0, bare_ms = 0.0, tracer_cpu_ms = 0.0, bare_cpu_ms = 0.0;
  size_t index = 0;
  for (const CameraBookmark& b : s.bookmarks) {
    for (int eye = 0; eye < 2; ++eye) {
      const std::optional<Camera> camera = bench_eye_camera(b, eye, display);
      if (!camera || index >= tracer_eyes.size()) continue;
      const EyeResult& te = tracer_eyes[index++];
      const server::TraceStats& tstats = te.stats;
      const double tms = te.ms;
      CapturedRays rays = capture_rays(tracer.embree_scene(), s.scene.lights, *camera, server::SkipOptions{}, threads);
      std::vector<double> primary_ms, shadow_ms, total_ms, cpu_ms;
      BareLoopResult last;
      for (int r = 0; r < o.repeat; ++r) {
        last = run_bare_loop(handle, rays, threads);
        primary_ms.push_back(last.primary_ms);
        shadow_ms.push_back(last.shadow_ms);
        total_ms.push_back(last.primary_ms + last.shadow_ms);
        cpu_ms.push_back(last.cpu_ms);
      }
      const double cpu_med = median(cpu_ms);
      const uint64_t n = rays.primary.size() + rays.shadow.size();
      const double med = median(total_ms);
      const uint64_t traced = tstats.primary_rays + tstats.shadow_rays;
      Json j = base_record("bare", s);
      j["bookmark"] = b.name;
      j["eye"] = eye == 0 ? "left" : "right";
      j["resolution"] = size_json(display);
      j["threads"] = threads;
      j["rays"] = Json{{"primary", rays.primary.size()}, {"shadow", rays.shadow.size()},
                       {"primary_hits", last.primary_hits}, {"occluded", last.occluded}};
      j["tracer_rays"] = Json{{"primary", tstats.primary_rays}, {"shadow", tstats.shadow_rays},
                              {"hit_pixels", tstats.pixels - tstats.background_pixels}};
      j["bare_ms"] = Json{{"median", round3(med)}, {"primary_median", round3(median(primary_ms))},
                          {"shadow_median", round3(median(shadow_ms))}};
      j["bare_cpu_ms_median"] = round3(cpu_med);
      j["bare_mrays_s"] = mrays_per_s(n, med);
      j["bare_mrays_per_cpu_s"] = mrays_per_s(n, cpu_med);
      j["tracer_ms_median"] = round3(tms);
      j["tracer_cpu_ms_median"] = round3(te.cpu_ms);
      j["tracer_mrays_s"] = mrays_per_s(traced, tms);
      j["tracer_mrays_per_cpu_s"] = mrays_per_s(traced, te.cpu_ms);
      j["tracer_vs_bare"] = round3(rate_ratio(traced, tms, n, med));
      j["tracer_vs_bare_cpu"] = round3(rate_ratio(traced, te.cpu_ms, n, cpu_med));
      emit(j);
      tracer_rays += traced;
      tracer_ms += tms;
      tracer_cpu_ms += te.cpu_ms;
      bare_rays += n;
      bare_ms += med;
      bare_cpu_ms += cpu_med;
    }
  }
  Json j = base_record("summary", s);
  j["kind"] = "bare_vs_tracer";
  j["resolution"] = size_json(display);
  j["threads"] = threads;
  j["eyes"] = index;
  j["bare_mrays_s"] = mrays_per_s(bare_rays, bare_ms);
  j["tracer_mrays_s"] = mrays_per_s(tracer_rays, tracer_ms);
  j["bare_mrays_per_cpu_s"] = mrays_per_s(bare_rays, bare_cpu_ms);
  j["tracer_mrays_per_cpu_s"] = mrays_per_s(tracer_rays, tracer_cpu_ms);
  j["tracer_vs_bare"] = round3(rate_ratio(tracer_rays, tracer_ms, bare_rays, bare_ms));
  j["tracer_vs_bare_cpu"] = round3(rate_ratio(tracer_rays, tracer_cpu_ms, bare_rays, bare_cpu_ms));
  emit(j);
}

// Error records decide the exit code: a scene that cannot be loaded is bad input (2), anything else that could
// not be measured a failure (1).
int g_input_errors = 0;
int g_errors = 0;

void emit_error(const std::string& scene, const std::string& what, const std::string& message) {
  emit(Json{{"record", "error"}, {"scene", scene}, {"what", what}, {"error", message}});
  ++(what == "load" || what == "scenes" || what == "bookmarks" ? g_input_errors : g_errors);
}

void bench_scene(const std::string& path, const TraceBenchOptions& o, unsigned threads) {
  LoadedScene s;
  s.path = path;
  const auto t0 = std::chrono::steady_clock::now();
  SceneLoadResult loaded = load_scene(path);
  s.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!loaded) return emit_error(path, "load", loaded.error);
  s.scene = std::move(*loaded.scene);
  const size_t own_lights = s.scene.lights.size();
  const double light_range = o.light_range >= 0.0 ? o.light_range : bench::default_bench_light_range(s.scene, o.lights);
  if (o.lights > own_lights) bench::add_bench_lights(s.scene, o.lights, light_range);
  try {
    s.bookmarks = bench_bookmarks(path, s.scene, s.bookmark_source);
  } catch (const std::exception& e) {
    return emit_error(path, "bookmarks", e.what());
  }
  if (o.bookmarks && s.bookmarks.size() > o.bookmarks) s.bookmarks.resize(o.bookmarks);
  Json info = base_record("scene", s);
  info["triangles"] = s.scene.triangle_count;
  info["meshes"] = s.scene.meshes.size();
  info["lights"] = s.scene.lights.size();
  if (s.scene.lights.size() > own_lights) {
    info["lights_own"] = own_lights;
    info["added_light_range_m"] = light_range;
  }
  info["load_ms"] = round3(s.load_ms);
  info["bookmarks_from"] = s.bookmark_source;
  Json names = Json::array();
  for (const auto& b : s.bookmarks) names.push_back(b.name);
  info["bookmarks"] = names;
  emit(info);

  server::TracerOptions skip_on, skip_off;
  skip_on.threads = skip_off.threads = threads;
  skip_off.skip = server::SkipOptions::none();
  try {
    auto with_skip = build_tracer(server::TracerBackend::kEmbree, s, skip_on);
    auto without_skip = build_tracer(server::TracerBackend::kEmbree, s, skip_off);
    if (const LightSlots* slots = with_skip->light_slots()) {
      Json j = base_record("light_slots", s);
      j["slots"] = slots->slot_count();
      j["global"] = slots->global_lights();
      j["lights_per_cell_max"] = slots->max_lights_per_cell();
      j["dropped"] = slots->dropped().size();
      j["describe"] = slots->describe();
      emit(j);
    }
    for (const Extent& size : o.sizes) {
      const auto eyes = trace_views(*with_skip, s, size, skip_on.skip, o);
      trace_views(*without_skip, s, size, skip_off.skip, o);
      // The bare loop replays one ray per pixel and light, without light slots.
      if (o.bare && !with_skip->light_slots()) bare_views(dynamic_cast<const server::EmbreeTracer&>(*with_skip), s, size, eyes, threads, o);
    }
  } catch (const std::exception& e) {
    emit_error(path, "embree", e.what());
  }
  if (!o.vulkan) return;
  try {
    for (const server::TracerOptions* base : {&skip_on, &skip_off}) {
      server::TracerOptions vk = *base;
      vk.vk_device = "lavapipe";
      auto tracer = build_tracer(server::TracerBackend::kVulkan, s, vk);
      trace_views(*tracer, s, o.vulkan_size, vk.skip, o);
    }
  } catch (const std::exception& e) {
    emit_error(path, "vulkan", e.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  TraceBenchOptions o;
  if (cli::asks_for_help(argc, argv)) return trace_bench_usage(stdout);
  if (wants_trace_sequence(argc, argv)) {
    try {
      return run_trace_sequence(argc, argv);
    } catch (const std::exception& e) {  // a trace or the truth that throws: said, exit 1
      std::fprintf(stderr, "trace_bench: %s\n", e.what());
      return exit_code::kFailure;
    }
  }
  if (!parse_trace_bench_args(argc, argv, o)) return trace_bench_usage();
  const unsigned threads = o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency());
  Json sizes = Json::array();
  for (const Extent& e : o.sizes) sizes.push_back(size_text(e));
  Json scenes = Json::array();
  for (const std::string& p : o.scenes) scenes.push_back(p);
  emit(Json{{"record", "run"},
            {"bench", "trace_bench"},
            {"cpu", cpu_model()},
            {"hardware_threads", std::thread::hardware_concurrency()},
            {"threads", threads},
            {"build_type", DHR_BUILD_TYPE},
            {"compiler", __VERSION__},
            {"embree", RTC_VERSION_STRING},
            {"quick", o.quick},
            {"soft_levels", o.soft_levels},
            {"repeat", o.repeat},
            {"sizes", sizes},
            {"vulkan_size", o.vulkan ? Json(size_text(o.vulkan_size)) : Json(nullptr)},
            {"scenes", scenes}});
  if (o.scenes.empty()) emit_error("", "scenes", "no scene found (give --scene PATH)");
  for (const std::string& path : o.scenes) bench_scene(path, o, threads);
  if (g_input_errors > 0) return exit_code::kUsage;
  return g_errors > 0 ? exit_code::kFailure : exit_code::kOk;
}
