#include "eval_run.hpp"

#include "plan/shipped_defaults.hpp"

#include "cli/exit_codes.hpp"

#include "traces/eye_model.hpp"
#include "log/log.hpp"
#include "eval_render.hpp"
#include "eval_results.hpp"
#include "eval_session.hpp"
#include "eval_truth.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "snapshot_crops.hpp"
#include "render/light_layout.hpp"
#include "bench_lights.hpp"
#include "json_writer.hpp"
#include "pose/trace_pose_source.hpp"
#include "vk/context.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <span>
#include <stdexcept>

namespace dhr::eval {
namespace {

namespace fs = std::filesystem;

constexpr double kMinWarmupMs = 250.0;

// --snapshot-crop: one picture per round trip and guard band, the methods in the order of the settings.
void write_crop_pictures(const RunOptions& options, const std::vector<Setting>& settings) {
  std::vector<CropPicture> pictures;
  for (const Setting& s : settings) {
    char rtt[32];
    std::snprintf(rtt, sizeof rtt, "%g", s.rtt_ms);  // as eval_session names the snapshots
    auto it = std::find_if(pictures.begin(), pictures.end(),
                           [&](const CropPicture& p) { return p.rtt == rtt && p.guard == s.guard; });
    if (it == pictures.end()) {
      CropPicture p;
      p.out_dir = options.out_dir;
      p.rtt = rtt;
      p.guard = s.guard;
      p.crop = *parse_crop(*options.snapshot_crop);
      pictures.push_back(p);
      it = pictures.end() - 1;
    }
    const std::string name = method_name(s.method);
    if (std::find(it->methods.begin(), it->methods.end(), name) == it->methods.end()) it->methods.push_back(name);
  }
  for (const CropPicture& p : pictures) {
    std::string error;
    const auto path = write_crop_picture(p, &error);
    if (!path) throw std::runtime_error("--snapshot-crop: " + error);
    log::info("dhr-eval: %s", path->c_str());
  }
}

// The part of the trace from start_s on (the first sample interpolated at exactly start_s).
PoseTrace skip_start(const PoseTrace& trace, double start_s) {
  if (start_s <= 0.0) return trace;
  const double t0 = trace.start_time() + start_s;
  PoseTrace out = trace;
  out.samples.clear();
  out.samples.push_back(trace.sample(t0));
  out.samples.front().time = t0;
  for (const TraceSample& s : trace.samples) {
    if (s.time > t0) out.samples.push_back(s);
  }
  return out;
}

bool write_file(const fs::path& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file << text;
  return static_cast<bool>(file);
}

void progress(uint64_t done, uint64_t total, size_t settings, double elapsed_s) {
  const int width = 30;
  const int filled = total > 0 ? static_cast<int>(width * done / total) : width;
  std::string bar(static_cast<size_t>(filled), '=');
  bar.resize(static_cast<size_t>(width), ' ');
  const double eta = done > 0 ? elapsed_s * static_cast<double>(total - done) / static_cast<double>(done) : 0.0;
  std::fprintf(stderr, "\r[%s] %3d%% frame %llu/%llu, %zu settings, %.0f s elapsed, ~%.0f s left ", bar.c_str(),
               total > 0 ? static_cast<int>(100 * done / total) : 100, static_cast<unsigned long long>(done),
               static_cast<unsigned long long>(total), settings, elapsed_s, eta);
  std::fflush(stderr);
}

// The trace the command line names: unreadable or malformed is bad input.
PoseTrace load_input_trace(const std::string& path) {
  try {
    return client::TracePoseSource::load(path);
  } catch (const std::exception& e) {
    throw cli::InputError(e.what());
  }
}

// The bit error of a headset that shades every light unshadowed: every surface pixel's every light fully lit,
// against the truth's masks (visibility_bit_error's basis: display pixels x lights).
double unshadowed_error(const Truth& truth, int eye, const VisibilityLayout& layout) {
  uint32_t lit = 0;
  for (uint32_t l = 0; l < layout.light_count; ++l) lit = layout.with_visibility(lit, l, 1.0f);
  VisibilityBuffer all_lit = truth.mask[eye];
  for (size_t p = 0; p < all_lit.pixel_count(); ++p)
    if (truth.exact[eye].surface[p]) all_lit.set_mask_at(p, lit);
  const std::optional<BitError> e = visibility_bit_error(all_lit, truth.mask[eye]);
  return e ? e->fraction() : 0.0;
}

}  // namespace

int run_eval(const RunOptions& options, const std::string& command_line) {
  const auto started = std::chrono::steady_clock::now();
  try {
    SceneLoadResult loaded = load_scene(options.scene);
    if (!loaded) throw cli::InputError(loaded.error);
    Scene& scene = *loaded.scene;
    const double light_range = options.light_range >= 0.0 ? options.light_range
                               : options.lights > scene.lights.size()
                                   ? bench::default_bench_light_range(scene, options.lights)
                                   : 0.0;
    if (options.lights > scene.lights.size()) bench::add_bench_lights(scene, options.lights, light_range);
    // More than kMaxLights lights share light slots (scene/light_slots.hpp): evaluated for hard lights in a static
    // scene. The client's shadow maps hold at most kMaxLights lights, so it has none here: `local` is the headset
    // shading every light unshadowed, and the other methods' undecided bits take the samples' vote.
    const bool light_slots = scene.lights.size() > kMaxLights;
    if (light_slots) {
      const std::string many = options.scene + ": " + std::to_string(scene.lights.size()) + " lights share light slots";
      if (!scene.animation.empty())
        throw cli::InputError(many + ", which need a scene without animation (the scene has animations)");
      if (scene.has_soft_lights())
        throw cli::InputError(many + ", and dhr-eval evaluates them for hard lights only (the scene has lights with "
                              "an extent)");
      for (const MethodSpec& m : options.methods)
        if (!uses_server_visibility(m))
          log::warn("dhr-eval: %s: --method %s is the headset without shadows (its shadow maps hold at most 32 lights)",
                    many.c_str(), method_name(m).c_str());
    }
    if (options.truth_first_samples > options.truth_samples)
      throw cli::InputError("--truth-first-samples is above --truth-samples");
    if (options.server_soft.initial_samples > options.server_soft.max_samples)
      throw cli::InputError("--soft-first-samples is above --soft-samples");
    // Every light with slots (the truth traces the fields), else the first kMaxLights.
    const std::span<const SceneLight> lights =
        std::span(scene.lights).first(light_slots ? scene.lights.size() : std::min<size_t>(scene.lights.size(), kMaxLights));
    const uint32_t soft_lights = light_slots ? 0u : render::soft_light_mask(render::layout_for_lights(lights));
    PoseTrace trace = load_input_trace(options.trace);
    if (options.trace_start_s >= trace.duration()) {
      throw cli::InputError(options.trace + ": --trace-start is past the end of the trace");
    }
    trace = skip_start(trace, options.trace_start_s);
    std::string placement_note;
    const TracePlacement placement = default_trace_placement(options.scene, &placement_note);
    const EyeModel eyes = EyeModel::typical_headset();
    client::TracePoseSource source(trace, eyes, placement, fs::path(options.trace).filename().string());

    if (options.snapshot_crop) {
      const auto crop = parse_crop(*options.snapshot_crop);
      if (!crop) throw cli::InputError("--snapshot-crop '" + *options.snapshot_crop + "': expected X,Y,W,H");
      if (uint64_t{crop->x} + crop->width > options.eye.width || uint64_t{crop->y} + crop->height > options.eye.height) {
        throw cli::InputError("--snapshot-crop '" + *options.snapshot_crop + "' does not lie inside the " +
                              std::to_string(options.eye.width) + "x" + std::to_string(options.eye.height) + " eye");
      }
    }
    const std::vector<Setting> settings = expand_settings(options);
    if (settings.empty()) throw std::runtime_error("no settings to run (empty lists)");
    double max_rtt = 0.0;
    for (const Setting& s : settings) max_rtt = std::max(max_rtt, s.rtt_ms);
    const double period_ms = static_cast<double>(client::kVirtualFramePeriodNs) * 1e-6;
    const uint64_t warmup = static_cast<uint64_t>(
        std::ceil(std::max(kMinWarmupMs, max_rtt + options.server_ms + 4.0 * options.jitter_ms + 30.0) / period_ms));
    const uint64_t available = source.frame_count();
    if (available <= warmup) {
      throw cli::InputError(options.trace + ": too short for the warm-up of " + std::to_string(warmup) + " frames");
    }
    const uint64_t frames = options.frames > 0 ? std::min(options.frames, available - warmup) : available - warmup;
    if (options.snapshot_frame && *options.snapshot_frame >= frames) {
      throw cli::InputError("--snapshot-frame " + std::to_string(*options.snapshot_frame) + ": the run measures " +
                               std::to_string(frames) + " frames (0.." + std::to_string(frames - 1) + ")");
    }

    fs::create_directories(options.out_dir);
    vk::ContextOptions vk_options;
    vk_options.app_name = "dhr-eval";
    const std::unique_ptr<vk::Context> context = vk::Context::create(vk_options);
    // --render-path shipped: the client's rule on this device (forward where it applies, unless a discrete GPU).
    const bool forward = options.shipped_path &&
                         client::forward_pass_for(client::shipped::kRenderPath, context->info().is_discrete_gpu);
    EyeRenderer renderer(*context, scene, options.eye, options.shadow_maps, forward);
    server::TracerOptions tracer_options;
    tracer_options.threads = options.threads;
    tracer_options.soft = options.server_soft;
    const auto tracer = std::make_unique<server::EmbreeTracer>(scene, tracer_options);
    const TruthScene truth_scene{tracer.get(), &scene, lights, renderer.layout(), light_slots};
    TruthSampling truth_sampling;
    truth_sampling.first_samples = options.truth_first_samples;
    truth_sampling.samples = options.truth_samples;
    truth_sampling.threads = options.threads;

    std::vector<FramePose> history;
    double truth_s = 0.0;  // wall time of the ground truth (trace and pictures)
    const uint64_t total = warmup + frames;
    SessionShared shared{tracer.get(), &renderer, &scene, options.shadow_maps, forward, options.eye,
                         renderer.light_count(), soft_lights, &history, total, light_slots ? renderer.light_count() : 0u};
    double unshadowed_bit_error = 0.0;  // every light lit on every surface: the headset without shadows
    uint64_t truth_eyes = 0;

    std::vector<std::unique_ptr<SettingSession>> sessions;
    for (const Setting& s : settings) {
      const auto index = static_cast<uint32_t>(sessions.size());
      sessions.push_back(std::make_unique<SettingSession>(s, options, shared, index));
      if (options.snapshot_frame) sessions.back()->snapshot_at(warmup + *options.snapshot_frame);
    }

    log::info("dhr-eval: %zu settings, %llu warm-up + %llu measured frames, eyes %ux%u, %s, tracer %s",
              settings.size(), static_cast<unsigned long long>(warmup), static_cast<unsigned long long>(frames),
              options.eye.width, options.eye.height, context->info().name.c_str(),
              tracer->device_description().c_str());
    for (uint64_t i = 0; i < total; ++i) {
      FramePose sample;
      if (!source.next(sample)) break;
      sample.views = wire_views(sample.views);
      history.push_back(sample);
      const bool measured = i >= warmup;
      std::map<std::string, Truth> truths;  // per guard band
      if (measured) {
        for (const Setting& s : settings) {
          if (truths.contains(s.guard)) continue;
          const auto truth_start = std::chrono::steady_clock::now();
          truths[s.guard] =
              ground_truth(truth_scene, truth_sampling, renderer, options.eye, s.guard_band, sample);
          if (truths.size() == 1) {
            for (int eye = 0; eye < 2; ++eye) unshadowed_bit_error += unshadowed_error(truths[s.guard], eye, renderer.layout());
            truth_eyes += 2;
          }
          truth_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - truth_start).count();
        }
      }
      for (auto& session : sessions) {
        session->advance(sample);
        if (measured) session->measure(truths.at(session->setting().guard));
      }
      if (options.progress && (i % 4 == 0 || i + 1 == total)) {
        progress(i + 1, total, sessions.size(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
      }
    }
    if (options.progress) std::fprintf(stderr, "\n");

    std::vector<SettingResult> results;
    for (const auto& session : sessions) results.push_back(summarize(session->setting(), session->totals(), frames));
    const fs::path out(options.out_dir);
    bench::JsonWriter meta;
    meta.begin_object();
    meta.value("command", command_line);
    meta.value("scene", options.scene);
    meta.value("added_light_range_m", options.lights > 0 ? light_range : 0.0, 3);
    meta.value("trace", options.trace);
    meta.value("trace_start_s", options.trace_start_s, 3);
    meta.value("placement", placement_note);
    meta.value("eye_width", options.eye.width);
    meta.value("eye_height", options.eye.height);
    meta.value("frame_rate_hz", 1e9 / static_cast<double>(client::kVirtualFramePeriodNs), 3);
    meta.value("warmup_frames", static_cast<unsigned long long>(warmup));
    meta.value("frames", static_cast<unsigned long long>(frames));
    meta.value("render_path", options.shipped_path ? "shipped" : "deferred");
    meta.value("lights", renderer.light_count());  // mask fields: with light slots, the slots the lights share
    meta.value("scene_lights", static_cast<unsigned long long>(scene.lights.size()));
    meta.value("light_slots", light_slots);
    meta.value("unshadowed_bit_error", truth_eyes ? unshadowed_bit_error / static_cast<double>(truth_eyes) : 0.0, 8);
    meta.value("soft_lights", std::popcount(soft_lights));
    // Per pixel and light with an extent (a punctual light: one ray): the server's, the truth's.
    meta.value("server_soft_first_samples", options.server_soft.initial_samples);
    meta.value("server_soft_samples", options.server_soft.max_samples);
    meta.value("truth_first_samples", truth_sampling.first_samples);
    meta.value("truth_samples", truth_sampling.samples);
    meta.value("truth_salt", truth_sampling.salt);
    meta.value("truth_s", truth_s, 1);
    meta.value("jitter_ms", options.jitter_ms, 3);
    meta.value("loss", options.loss, 4);
    meta.value("codec", options.codec_v2 ? "v2" : "v1");
    meta.value("predict_window_ms", options.predict_window_ms, 3);
    meta.value("predict_quadratic_ms", options.predict_quadratic_ms, 3);
    meta.value("predict_max_horizon_ms", options.predict_max_horizon_ms, 3);
    meta.value("server_model_ms", options.server_ms, 3);
    meta.value("seed", static_cast<unsigned long long>(options.seed));
    meta.value("client_device", context->info().name + " (" + context->info().driver_info + ")");
    meta.value("tracer", tracer->device_description());
    meta.value("wall_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), 1);
    meta.end_object();
    if (!write_file(out / "results.json", results_json(results)) || !write_file(out / "results.csv", results_csv(results)) ||
        !write_file(out / "run.json", meta.str() + "\n")) {
      throw std::runtime_error(options.out_dir + ": cannot write the results");
    }
    if (options.snapshot_crop) write_crop_pictures(options, settings);
    std::printf("%s", results_table(results).c_str());
    std::printf("dhr-eval: %llu frames x 2 eyes x %zu settings in %.1f s; results in %s\n",
                static_cast<unsigned long long>(frames), settings.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
                (out / "results.json").string().c_str());
    return exit_code::kOk;
  } catch (const cli::InputError& e) {
    std::fprintf(stderr, "dhr-eval: %s\n", e.what());
    return exit_code::kUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dhr-eval: %s\n", e.what());
    return exit_code::kFailure;
  }
}

}  // namespace dhr::eval
