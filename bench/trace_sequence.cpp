#include "trace_sequence.hpp"

#include "bench_lights.hpp"
#include "bench_timing.hpp"
#include "bench_views.hpp"
#include "sequence_truth.hpp"
#include "cli/exit_codes.hpp"
#include "scene/light_slots.hpp"
#include "scene/scene.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "trace/stats_json.hpp"
#include "trace/visibility_tracer.hpp"
#include "traces/eye_model.hpp"
#include "traces/pose_trace.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace dhr::bench {
namespace {

using Json = nlohmann::ordered_json;
constexpr double kFramePeriodS = 1.0 / 90.0;
constexpr double kSessionStaggerS = 5.0;  // sessions beyond the traces given start this much later in them

struct SequenceArgs {
  std::string scene = std::string(DHR_SHARED_DATA_DIR) + "/scenes/living_room.glb";
  std::vector<std::string> traces;
  uint32_t frames = 90;
  Extent size{1984, 1116};
  uint32_t sessions = 0;  // 0: one per trace
  double trace_start_s = 2.0;
  unsigned threads = 0;
  bool soft_levels = false;
  bool shared = true;
  bool refresh = true;
  bool blocks = true;  // rule 1 (trace/reuse)
  bool pairs = true;   // rule 2
  uint32_t soft_history = server::ReuseOptions{}.soft_history;  // --soft-history N (0: off)
  float soft_hysteresis = server::ReuseOptions{}.soft_hysteresis;  // --soft-hysteresis L (levels; 0: off)
  uint32_t truth_every = 30;  // soft levels: the truth of every camera of every this many frames (0: none)
  uint32_t lights = 0;        // --lights: point lights added up to this many (bench_lights.hpp); 0: the scene's
  double light_range = -1.0;  // --light-range (metres); < 0: default_bench_light_range
};

int usage(FILE* to) {
  std::fprintf(to,
               "usage: trace_bench --trace PATH [--trace PATH]... [--scene PATH] [--frames N] [--size WxH] "
               "[--sessions K] [--trace-start S] [--threads N]\n"
               "       [--soft-levels [--truth-every N] [--soft-history N] [--soft-hysteresis L]] "
               "[--no-shared] "
               "[--no-refresh] [--no-blocks] [--no-pairs] [--lights N [--light-range M]]\n");
  return to == stderr ? exit_code::kUsage : exit_code::kOk;
}

bool parse(int argc, char** argv, SequenceArgs& a) {
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (k == "--soft-levels") { a.soft_levels = true; continue; }
    if (k == "--no-shared") { a.shared = false; continue; }
    if (k == "--no-refresh") { a.refresh = false; continue; }
    if (k == "--no-blocks") { a.blocks = false; continue; }
    if (k == "--no-pairs") { a.pairs = false; continue; }
    if (i + 1 >= argc) return false;
    const std::string v = argv[++i];
    if (v.empty()) return false;  // strtol would read "" as 0
    char* end = nullptr;
    if (k == "--trace") {
      a.traces.push_back(v);
    } else if (k == "--scene") {
      a.scene = v;
    } else if (k == "--frames") {
      const long n = std::strtol(v.c_str(), &end, 10);
      if (*end || n < 1 || n > 100000) return false;
      a.frames = static_cast<uint32_t>(n);
    } else if (k == "--truth-every") {
      const long n = std::strtol(v.c_str(), &end, 10);
      if (*end || n < 0 || n > 100000) return false;
      a.truth_every = static_cast<uint32_t>(n);
    } else if (k == "--soft-history") {
      const long n = std::strtol(v.c_str(), &end, 10);
      if (*end || n < 0 || n > 65535) return false;
      a.soft_history = static_cast<uint32_t>(n);
    } else if (k == "--soft-hysteresis") {
      const double x = std::strtod(v.c_str(), &end);
      if (*end || !std::isfinite(x) || x < 0.0 || x > 7.0) return false;
      a.soft_hysteresis = static_cast<float>(x);
    } else if (k == "--sessions") {
      const long n = std::strtol(v.c_str(), &end, 10);
      if (*end || n < 1 || n > 64) return false;
      a.sessions = static_cast<uint32_t>(n);
    } else if (k == "--lights") {
      const long n = std::strtol(v.c_str(), &end, 10);
      if (*end || n < 1 || n > static_cast<long>(kMaxSlotLights)) return false;
      a.lights = static_cast<uint32_t>(n);
    } else if (k == "--light-range") {
      a.light_range = std::strtod(v.c_str(), &end);
      if (*end || !std::isfinite(a.light_range) || a.light_range < 0.0 || a.light_range > 1000.0) return false;
    } else if (k == "--trace-start") {
      a.trace_start_s = std::strtod(v.c_str(), &end);
      if (*end || !std::isfinite(a.trace_start_s) || a.trace_start_s < 0.0) return false;
    } else if (k == "--threads") {
      const long n = std::strtol(v.c_str(), &end, 10);
      if (*end || n < 0 || n > 256) return false;
      a.threads = static_cast<unsigned>(n);
    } else if (k == "--size") {
      unsigned w = 0, h = 0;
      char tail = 0;
      if (std::sscanf(v.c_str(), "%ux%u%c", &w, &h, &tail) != 2 || w < 16 || h < 16 || w > 3800 || h > 3800)
        return false;
      a.size = Extent{w, h};
    } else {
      return false;
    }
  }
  if (a.traces.empty()) return false;
  if (a.sessions == 0) a.sessions = static_cast<uint32_t>(a.traces.size());
  return true;
}

// Differences between a reusing trace and the exhaustive one of the same camera, over hit pixels (a pixel whose
// exhaustive mask or reused mask has any bit, or that the exhaustive trace hit: counted by the caller's hits).
struct Difference {
  uint64_t hard_bits = 0, hard_differing = 0;
  uint64_t soft_pairs = 0, soft_differing = 0;
  double soft_abs_difference = 0.0;  // sum over soft pairs of |visibility reused - visibility exhaustive|
};

void compare(const VisibilityBuffer& exact, const VisibilityBuffer& reused, const VisibilityLayout& layout,
             uint64_t hit_pixels, Difference& d) {
  uint32_t hard_lights = 0, soft_lights = 0;
  for (uint32_t li = 0; li < layout.light_count; ++li) (layout.is_soft(li) ? soft_lights : hard_lights) += 1;
  d.hard_bits += hit_pixels * hard_lights;
  d.soft_pairs += hit_pixels * soft_lights;
  for (size_t p = 0; p < exact.pixel_count(); ++p) {
    const uint32_t a = exact.mask_at(p), b = reused.mask_at(p);
    if (a == b) continue;
    for (uint32_t li = 0; li < layout.light_count; ++li) {
      const uint32_t field = ((1u << layout.bits[li]) - 1u) << layout.offset[li];
      if ((a & field) == (b & field)) continue;
      ++(layout.is_soft(li) ? d.soft_differing : d.hard_differing);
      if (layout.is_soft(li))
        d.soft_abs_difference +=
            std::fabs(static_cast<double>(layout.visibility(a, li)) - static_cast<double>(layout.visibility(b, li)));
    }
  }
}

struct Totals {
  double rays = 0, shadow_rays = 0, reused_pixels = 0, reused_pairs = 0, refreshed = 0;
  std::vector<double> ms;
};

Json totals_json(const Totals& t, double eyes) {
  return Json{{"rays_per_eye_frame", std::round(t.rays / eyes)},
              {"shadow_rays_per_eye_frame", std::round(t.shadow_rays / eyes)},
              {"reused_pixels_per_eye_frame", std::round(t.reused_pixels / eyes)},
              {"reused_pairs_per_eye_frame", std::round(t.reused_pairs / eyes)},
              {"refreshed_pixels_per_eye_frame", std::round(t.refreshed / eyes)},
              {"trace_ms_per_eye", median(t.ms, 0.0)}};
}

}  // namespace

bool wants_trace_sequence(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--trace") return true;
  return false;
}

int run_trace_sequence(int argc, char** argv) {
  SequenceArgs a;
  if (!parse(argc, argv, a)) return usage(stderr);
  SceneLoadResult loaded = load_scene(a.scene);
  if (!loaded) {
    std::fprintf(stderr, "trace_bench: %s\n", loaded.error.c_str());
    return exit_code::kUsage;
  }
  Scene& scene = *loaded.scene;
  const uint32_t own_lights = static_cast<uint32_t>(scene.lights.size());
  const double light_range =
      a.light_range >= 0.0 ? a.light_range : a.lights > own_lights ? default_bench_light_range(scene, a.lights) : 0.0;
  if (a.lights > own_lights) add_bench_lights(scene, a.lights, light_range);
  std::vector<PoseTrace> traces;
  for (const std::string& path : a.traces) {
    TraceReadResult read = read_pose_trace(path);
    if (!read || read.trace->empty()) {
      std::fprintf(stderr, "trace_bench: %s\n", read ? (path + ": empty trace").c_str() : read.error.c_str());
      return exit_code::kUsage;
    }
    traces.push_back(std::move(*read.trace));
  }
  const TracePlacement placement = default_trace_placement(a.scene);
  const EyeModel eyes = EyeModel::typical_headset();
  Extent display;
  GuardBand guard;
  split_guard_band(a.size, display, guard);
  const TracedFormat format{display, guard};

  server::TracerOptions tracer_options;
  tracer_options.threads = a.threads;
  std::unique_ptr<server::VisibilityTracer> tracer;
  try {
    tracer = server::create_tracer(server::TracerBackend::kEmbree, scene, tracer_options);
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "trace_bench: %s\n", ex.what());
    return exit_code::kFailure;
  }
  const VisibilityLayout layout = a.soft_levels ? server::layout_for_lights(tracer->light_extents(),
                                                                            tracer->light_count())
                                                : VisibilityLayout::hard(tracer->light_count());

  // The truth for the soft fields' visibility_error: static scenes (the lights at rest are the scene's).
  std::unique_ptr<SequenceTruth> truth;
  if (a.soft_levels && a.truth_every > 0) {
    if (tracer->moves()) {
      std::fprintf(stderr, "trace_bench: a moving scene: no truth, so no visibility_error\n");
    } else {
      const auto& embree = dynamic_cast<const server::EmbreeTracer&>(*tracer);
      truth = std::make_unique<SequenceTruth>(embree.embree_scene(), scene.lights, layout, a.threads);
    }
  }

  const uint32_t S = a.sessions;
  // A session that runs past its trace's end holds the last pose (PoseTrace::sample): said, not silent.
  for (uint32_t s = 0; s < S; ++s) {
    const PoseTrace& trace = traces[s % traces.size()];
    const double needed = a.trace_start_s + kSessionStaggerS * (s / traces.size()) + (a.frames - 1) * kFramePeriodS;
    if (needed > trace.duration())
      std::fprintf(stderr,
                   "trace_bench: warning: session %u needs %.2f s of %s, which lasts %.2f s: its last pose is held "
                   "from there on\n",
                   s, needed, a.traces[s % a.traces.size()].c_str(), trace.duration());
  }
  // Per session and eye: the newest reusing trace's record and the one being written (swapped after each trace).
  std::vector<std::array<server::ReuseFrame, 2>> newest(S), writing(S);
  std::vector<Pose> T_scene_trace(S);
  for (uint32_t s = 0; s < S; ++s)
    T_scene_trace[s] = placement_transform(placement, traces[s % traces.size()].samples.front().head);
  Totals exhaustive, reusing;
  std::vector<Totals> per_session(S);
  Difference diff;
  VisibilityBuffer exact, reused;
  const auto start = std::chrono::steady_clock::now();
  for (uint32_t f = 0; f < a.frames; ++f) {
    tracer->set_scene_time(f * kFramePeriodS);
    for (uint32_t s = 0; s < S; ++s) {
      const PoseTrace& trace = traces[s % traces.size()];
      const double t = trace.start_time() + a.trace_start_s + kSessionStaggerS * (s / traces.size()) + f * kFramePeriodS;
      const std::array<View, 2> views = trace_views(trace, trace.sample(t), eyes, T_scene_trace[s]);
      for (int e = 0; e < 2; ++e) {
        const Camera camera = format.camera(views[static_cast<size_t>(e)]);
        server::TraceStats xs, rs;
        tracer->trace_layout(camera, layout, exact, xs);
        server::ReuseRequest request;
        request.previous = newest[s][e].valid() ? &newest[s][e] : nullptr;
        request.record = &writing[s][e];
        request.options.refresh = a.refresh;
        request.options.whole_pixels = a.blocks;
        request.options.pairs = a.pairs;
        request.options.soft_history = a.soft_history;
        request.options.soft_hysteresis = a.soft_hysteresis;
        if (a.shared) {
          if (e == 1) request.shared.push_back(&newest[s][0]);  // this frame's left eye (already swapped in)
          for (uint32_t o = 0; o < S; ++o)
            if (o != s) request.shared.push_back(&newest[o][static_cast<size_t>(e)]);
        }
        tracer->trace_reusing(camera, layout, request, reused, rs);
        std::swap(newest[s][e], writing[s][e]);
        compare(exact, reused, layout, xs.pixels - xs.background_pixels, diff);
        if (truth && (f + 1) % a.truth_every == 0) truth->add(camera, exact, reused);
        exhaustive.rays += static_cast<double>(xs.primary_rays + xs.shadow_rays);
        exhaustive.shadow_rays += static_cast<double>(xs.shadow_rays);
        exhaustive.ms.push_back(xs.trace_ms);
        for (Totals* tot : {&reusing, &per_session[s]}) {
          tot->rays += static_cast<double>(rs.primary_rays + rs.shadow_rays);
          tot->shadow_rays += static_cast<double>(rs.shadow_rays);
          tot->reused_pixels += static_cast<double>(rs.reused_pixels);
          tot->reused_pairs += static_cast<double>(rs.reused_pairs);
          tot->refreshed += static_cast<double>(rs.refreshed_pixels);
          tot->ms.push_back(rs.trace_ms);
        }
      }
    }
    std::fprintf(stderr, "\rtrace_bench: frame %u/%u (%.0f s)", f + 1, a.frames, ms_since(start) / 1e3);
  }
  std::fprintf(stderr, "\n");

  const double eyes_traced = 2.0 * a.frames * S;
  Json out = totals_json(reusing, eyes_traced);
  out["exhaustive_rays_per_eye_frame"] = std::round(exhaustive.rays / eyes_traced);
  out["exhaustive_shadow_rays_per_eye_frame"] = std::round(exhaustive.shadow_rays / eyes_traced);
  out["exhaustive_trace_ms_per_eye"] = median(exhaustive.ms, 0.0);
  out["rays_ratio"] = exhaustive.rays > 0 ? reusing.rays / exhaustive.rays : 0.0;
  out["shadow_rays_ratio"] = exhaustive.shadow_rays > 0 ? reusing.shadow_rays / exhaustive.shadow_rays : 0.0;
  out["trace_ms_ratio"] = median(exhaustive.ms, 0.0) > 0 ? median(reusing.ms, 0.0) / median(exhaustive.ms, 0.0) : 0.0;
  out["differing_bits_frac"] = diff.hard_bits ? static_cast<double>(diff.hard_differing) / diff.hard_bits : 0.0;
  out["differing_bits"] = diff.hard_differing;
  out["differing_levels_frac"] = diff.soft_pairs ? static_cast<double>(diff.soft_differing) / diff.soft_pairs : 0.0;
  // Mean |k reused - k exhaustive| over soft pairs: the most reuse can change the visibility_error against any
  // reference (triangle inequality).
  out["levels_mean_abs_difference"] = diff.soft_pairs ? diff.soft_abs_difference / diff.soft_pairs : 0.0;
  if (truth) {
    // Mean |k - k truth| over the surface pixels' soft lights of the cameras of every --truth-every'th frame.
    out["visibility_error"] = truth->reused.mean();
    out["exhaustive_visibility_error"] = truth->exhaustive.mean();
    out["truth"] = Json{{"cameras", truth->cameras},
                        {"every_frames", a.truth_every},
                        {"first_samples", kTruthFirstSamples},
                        {"samples", kTruthSamples},
                        {"pairs", truth->reused.pairs},
                        {"trace_ms", truth->ms}};
  }
  Json sessions = Json::array();
  for (uint32_t s = 0; s < S; ++s) {
    Json j = totals_json(per_session[s], 2.0 * a.frames);
    j["trace"] = a.traces[s % a.traces.size()];
    sessions.push_back(j);
  }
  Json head{{"record", "sequence"},
            {"scene", a.scene},
            {"device", tracer->device_description()},
            {"size", std::to_string(a.size.width) + "x" + std::to_string(a.size.height)},
            {"frames", a.frames},
            {"sessions", S},
            {"shared", a.shared},
            {"refresh", a.refresh},
            {"blocks", a.blocks},
            {"pairs", a.pairs},
            {"soft_levels", a.soft_levels},
            {"soft_history", a.soft_history},
            {"soft_hysteresis", a.soft_hysteresis},
            {"lights", tracer->light_count()},  // mask fields: with more than 32 lights, the slots they share
            {"scene_lights", scene.lights.size()},
            {"added_light_range_m", light_range}};
  for (auto& [k, v] : out.items()) head[k] = v;
  head["per_session"] = sessions;
  std::printf("%s\n", head.dump().c_str());
  return exit_code::kOk;
}

}  // namespace dhr::bench
