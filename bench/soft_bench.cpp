// soft_bench: fractional (soft) visibility on the Embree backend (server/trace/soft); one JSON object per line,
// never asserts.
//   soft_bench [--scene PATH] [--size WxH] [--bookmarks N] [--threads N] [--repeat N] [--initial N] [--max N]
//              [--ref N] [--radius M] [--sun-angle RAD] [--rect] [--no-check] [--quick]
// The scene's lights get an extent in code (the loader may not read area lights): every point/spot light without
// one a sphere of --radius metres (default 1 % of the scene's bounding-box diagonal), every directional light a
// disk of --sun-angle radians (default 0.05); --rect adds a rect light under the ceiling. Per bookmark (left eye,
// 90 degrees plus the server's guard band), against a converged reference (--ref uniform stratified samples per
// pair, an independent scramble; checked by a second reference with twice the samples):
//   adaptive      the defaults (or --initial/--max): rays per pair, share refined, trace ms, mean |f - ref|
//   uniform_equal uniform sampling with the counts just below and above the adaptive run's mean rays per pair
//   uniform_max   uniform sampling with --max samples everywhere
//   levels        per level count 2..16: the error of the quantized adaptive fraction, and of quantizing alone
//   hard          the hard-shadow tracer on the same scene with the extents removed (trace ms), for scale
// Errors are means over the pairs whose reference took samples (the light can contribute) and over the penumbra
// (0 < ref < 1). docs/server.md ("Soft visibility") has the measured numbers and the command.
#include "bench_timing.hpp"
#include "bench_views.hpp"
#include "cli/exit_codes.hpp"
#include "cli/help_flag.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "trace/soft/soft_image.hpp"

#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace dhr;
using namespace dhr::bench;
using Json = nlohmann::ordered_json;

struct Options {
  std::string scene = std::string(DHR_SOURCE_DIR) + "/" + kDefaultScenePath;
  Extent size{160, 120};
  size_t bookmarks = 1;
  unsigned threads = 0;
  int repeat = 3;
  uint32_t initial = server::SoftOptions{}.initial_samples;
  uint32_t max = server::SoftOptions{}.max_samples;
  uint32_t ref = 1024;
  double radius = -1.0;  // < 0: 1 % of the diagonal
  double sun_angle = 0.05;
  bool rect = false;
  bool check = true;
  bool quick = false;
  server::SoftPattern pattern = server::SoftPattern::kPerLight;  // of the measured runs; references are per pixel
};

double round4(double v) { return std::round(v * 10000.0) / 10000.0; }

void emit(const Json& j) {
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
}

int usage(FILE* to = stderr) {
  std::fprintf(to,
               "usage: soft_bench [--scene PATH] [--size WxH] [--bookmarks N] [--threads N] [--repeat N] "
               "[--initial N] [--max N] [--ref N] [--radius M] [--sun-angle RAD] [--pattern per-light|per-pixel] [--rect] "
               "[--no-check] [--quick]\n");
  return to == stderr ? exit_code::kUsage : exit_code::kOk;
}

bool parse_args(int argc, char** argv, Options& o) {
  bool size_given = false, ref_given = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--rect") { o.rect = true; continue; }
    if (a == "--no-check") { o.check = false; continue; }
    if (a == "--quick") { o.quick = true; continue; }
    if (i + 1 >= argc) return false;
    const std::string v = argv[++i];
    const long n = std::atol(v.c_str());
    if (a == "--scene") {
      o.scene = v;
    } else if (a == "--size") {
      unsigned w = 0, h = 0;
      char tail = 0;
      if (std::sscanf(v.c_str(), "%ux%u%c", &w, &h, &tail) != 2 || w < 8 || h < 8 || w > 3800 || h > 3800)
        return false;
      o.size = Extent{w, h};
      size_given = true;
    } else if (a == "--bookmarks" && n >= 1) {
      o.bookmarks = static_cast<size_t>(n);
    } else if (a == "--threads" && n >= 0 && n <= 256) {
      o.threads = static_cast<unsigned>(n);
    } else if (a == "--repeat" && n >= 1 && n <= 100) {
      o.repeat = static_cast<int>(n);
    } else if (a == "--initial" && n >= 1) {
      o.initial = static_cast<uint32_t>(n);
    } else if (a == "--max" && n >= 1) {
      o.max = static_cast<uint32_t>(n);
    } else if (a == "--ref" && n >= 1 && n <= server::kMaxSoftSamples / 2) {
      o.ref = static_cast<uint32_t>(n);
      ref_given = true;
    } else if (a == "--radius") {
      o.radius = std::atof(v.c_str());
      if (!(o.radius > 0.0)) return false;
    } else if (a == "--pattern" && (v == "per-light" || v == "per-pixel")) {
      o.pattern = v == "per-light" ? server::SoftPattern::kPerLight : server::SoftPattern::kPerPixel;
    } else if (a == "--sun-angle") {
      o.sun_angle = std::atof(v.c_str());
      if (!(o.sun_angle > 0.0 && o.sun_angle < 1.0)) return false;
    } else {
      return false;
    }
  }
  if (o.quick) {  // smoke run: small, one bookmark, a cheap reference, no timing repeats
    if (!size_given) o.size = Extent{64, 48};
    if (!ref_given) o.ref = 128;
    o.repeat = 1;
  }
  return !server::validate_soft_options({o.initial, o.max, 0});
}

// Gives every light without an extent one (see the header comment); --rect adds a ceiling rect light.
void add_extents(Scene& scene, const Options& o, Json& out_lights) {
  const double radius = o.radius > 0.0 ? o.radius : 0.01 * static_cast<double>(scene.bounds.diagonal());
  for (SceneLight& l : scene.lights) {
    if (l.has_extent()) continue;
    if (l.type == SceneLight::Type::kDirectional) l.angle = static_cast<float>(o.sun_angle);
    if (l.type == SceneLight::Type::kPoint || l.type == SceneLight::Type::kSpot) l.radius = static_cast<float>(radius);
  }
  if (o.rect && scene.lights.size() < kMaxSceneLights) {
    const glm::vec3 c = scene.bounds.center(), s = scene.bounds.size();
    SceneLight r;
    r.type = SceneLight::Type::kRect;
    r.name = "bench_rect";
    r.position = glm::vec3(c.x, scene.bounds.min.y + 0.9f * s.y, c.z);
    r.direction = glm::vec3(0, -1, 0);
    r.tangent = glm::vec3(1, 0, 0);
    r.bitangent = glm::vec3(0, 0, -1);
    r.width = 0.25f * s.x;
    r.height = 0.25f * s.z;
    r.intensity = 5.0f;
    scene.lights.push_back(r);
  }
  out_lights = Json::array();
  for (const SceneLight& l : scene.lights)
    out_lights.push_back(Json{{"name", l.name}, {"type", l.type == SceneLight::Type::kRect ? "rect" : light_type_name(l.type)},
                              {"radius", l.radius}, {"angle", l.angle}, {"width", l.width}, {"height", l.height}});
}

struct Run {
  server::SoftImage image;
  server::SoftStats stats;
  double ms = 0.0;  // median trace ms
};

Run run_soft(const server::EmbreeScene& es, const Scene& scene, const Camera& camera, const server::SoftOptions& s,
             unsigned threads, int repeat) {
  server::SoftImageOptions o;
  o.sampling = s;
  o.threads = threads;
  Run r;
  std::vector<double> ms;
  for (int i = 0; i < repeat; ++i) {
    r.stats = server::trace_soft_image(es, scene.lights, camera, o, r.image);
    ms.push_back(r.stats.trace_ms);
  }
  r.ms = median(ms, 0.0);
  return r;
}

// Mean |f - ref| (f optionally quantized) over the pairs whose reference took samples, and over its penumbra.
struct Error {
  double all = 0.0, penumbra = 0.0;
  uint64_t pairs = 0, penumbra_pairs = 0;
};

Error error_against(const server::SoftImage& a, const server::SoftImage& ref, uint32_t levels = 0,
                    bool quantization_only = false) {
  Error e;
  for (size_t i = 0; i < ref.fraction.size(); ++i) {
    if (ref.rays[i] == 0) continue;
    float f = a.fraction[i];
    if (levels) f = dequantize(quantize(a.fraction[i], levels), levels);
    const double d = std::fabs(static_cast<double>(f) - static_cast<double>(quantization_only ? a.fraction[i] : ref.fraction[i]));
    e.all += d;
    ++e.pairs;
    if (ref.fraction[i] > 0.0f && ref.fraction[i] < 1.0f) {
      e.penumbra += d;
      ++e.penumbra_pairs;
    }
  }
  if (e.pairs) e.all /= static_cast<double>(e.pairs);
  if (e.penumbra_pairs) e.penumbra /= static_cast<double>(e.penumbra_pairs);
  return e;
}

Json error_json(const Error& e) {
  return Json{{"mean_abs", round4(e.all)}, {"penumbra_mean_abs", round4(e.penumbra)}};
}

Json run_json(const Run& r, const Error& e) {
  return Json{{"rays_per_pair", round4(r.stats.rays_per_pair())},
              {"refined_share", round4(r.stats.refined_share())},
              {"shadow_rays", r.stats.shadow_rays},
              {"trace_ms", round4(r.ms)},
              {"error", error_json(e)}};
}

int run_bench(const Options& o, unsigned threads) {
  SceneLoadResult loaded = load_scene(o.scene);
  if (!loaded) {
    emit(Json{{"record", "error"}, {"what", "load"}, {"error", loaded.error}});
    return exit_code::kUsage;
  }
  Scene scene = std::move(*loaded.scene);
  const Scene punctual = scene;  // before the extents: the hard tracer's scene
  Json lights;
  add_extents(scene, o, lights);
  std::string note;
  std::vector<CameraBookmark> bookmarks = bench_bookmarks(o.scene, scene, note);
  if (bookmarks.size() > o.bookmarks) bookmarks.resize(o.bookmarks);
  emit(Json{{"record", "scene"}, {"scene", o.scene}, {"triangles", scene.triangle_count}, {"lights", lights},
            {"bookmarks_from", note}});

  server::TracerOptions to;
  to.threads = threads;
  server::EmbreeTracer hard(punctual, to);  // its Embree scene serves the soft runs too (same geometry)
  const server::EmbreeScene& es = hard.embree_scene();
  const server::SoftOptions adaptive{o.initial, o.max, 0, o.pattern};
  for (const CameraBookmark& b : bookmarks) {
    const std::optional<Camera> camera = bench_eye_camera(b, 0, o.size);
    if (!camera) continue;
    const Run ref = run_soft(es, scene, *camera, server::SoftOptions::uniform(o.ref, 1, server::SoftPattern::kPerPixel), threads, 1);
    const Run ad = run_soft(es, scene, *camera, adaptive, threads, o.repeat);
    // Uniform sampling cannot take a fractional count: the two counts around the adaptive mean bracket it.
    const double mean_rays = ad.stats.rays_per_pair();
    Json uniform_equal = Json::array();
    for (const double n : {std::floor(mean_rays), std::ceil(mean_rays)}) {
      const uint32_t count = std::max<uint32_t>(1, static_cast<uint32_t>(n));
      if (!uniform_equal.empty() && uniform_equal.back()["samples"] == count) continue;
      const Run un = run_soft(es, scene, *camera, server::SoftOptions::uniform(count, 0, o.pattern), threads, o.repeat);
      Json u = run_json(un, error_against(un.image, ref.image));
      u["samples"] = count;
      uniform_equal.push_back(u);
    }
    const Run umax = run_soft(es, scene, *camera, server::SoftOptions::uniform(o.max, 0, o.pattern), threads, o.repeat);
    std::vector<double> hard_ms;
    VisibilityBuffer vis;
    server::TraceStats hs;
    for (int i = 0; i < o.repeat; ++i) {
      hard.trace(*camera, vis, hs);
      hard_ms.push_back(hs.trace_ms);
    }
    const Error ad_err = error_against(ad.image, ref.image);
    Json j{{"record", "soft"},
           {"scene", o.scene},
           {"bookmark", b.name},
           {"resolution", std::to_string(camera->extent.width) + "x" + std::to_string(camera->extent.height)},
           {"threads", threads},
           {"settings", Json{{"initial", o.initial}, {"max", o.max}, {"ref", o.ref}, {"repeat", o.repeat}, {"pattern", o.pattern == server::SoftPattern::kPerLight ? "per-light" : "per-pixel"}}},
           {"pixels", ad.stats.pixels},
           {"hit_pixels", ad.stats.pixels - ad.stats.background_pixels},
           {"pairs", ad.stats.pairs},
           {"contributing_pairs", ad.stats.contributing_pairs},
           {"reference_penumbra_pairs", ad_err.penumbra_pairs},
           {"adaptive", run_json(ad, ad_err)},
           {"uniform_equal", uniform_equal},
           {"uniform_max", run_json(umax, error_against(umax.image, ref.image))},
           {"reference_ms", round4(ref.ms)},
           {"hard", Json{{"trace_ms", round4(median(hard_ms, 0.0))}, {"shadow_rays", hs.shadow_rays}}}};
    Json levels = Json::array();
    for (uint32_t l : {2u, 4u, 8u, 16u}) {
      levels.push_back(Json{{"levels", l},
                            {"bits", static_cast<int>(std::ceil(std::log2(l)))},
                            {"error", error_json(error_against(ad.image, ref.image, l))},
                            {"quantization_only", error_json(error_against(ad.image, ref.image, l, true))}});
    }
    j["levels"] = levels;
    if (o.check) {
      // Convergence: a second reference with twice the samples and another scramble. The adaptive error against
      // it should change by < 1 %, and the references should differ by far less than that error.
      const Run ref2 = run_soft(es, scene, *camera, server::SoftOptions::uniform(2 * o.ref, 2, server::SoftPattern::kPerPixel), threads, 1);
      const Error e2 = error_against(ad.image, ref2.image);
      const Error between = error_against(ref.image, ref2.image);
      j["reference_check"] = Json{{"ref2_samples", 2 * o.ref},
                                  {"adaptive_error_vs_ref2", error_json(e2)},
                                  {"relative_change", ad_err.all > 0.0 ? round4(std::fabs(e2.all - ad_err.all) / ad_err.all) : 0.0},
                                  {"ref_vs_ref2", error_json(between)}};
    }
    emit(j);
  }
  return exit_code::kOk;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (cli::asks_for_help(argc, argv)) return usage(stdout);
  if (!parse_args(argc, argv, o)) return usage();
  const unsigned threads = o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency());
  emit(Json{{"record", "run"},
            {"bench", "soft_bench"},
            {"hardware_threads", std::thread::hardware_concurrency()},
            {"threads", threads},
            {"build_type", DHR_BUILD_TYPE},
            {"compiler", __VERSION__},
            {"embree", RTC_VERSION_STRING},
            {"quick", o.quick},
            {"size", std::to_string(o.size.width) + "x" + std::to_string(o.size.height)}});
  try {
    return run_bench(o, threads);
  } catch (const std::exception& e) {
    emit(Json{{"record", "error"}, {"what", "soft"}, {"error", e.what()}});
    return exit_code::kFailure;
  }
}
