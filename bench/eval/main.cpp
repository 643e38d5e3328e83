// dhr-eval: run time against error. `run` simulates the whole pipeline (VisibilityClient -> simulated network ->
// VisibilityService -> simulated network -> the client's real GPU passes) on a virtual 90 Hz clock over a sweep
// of settings, against the exactly traced ground truth; `report` turns the results into plots and Markdown;
// `make-trace` writes a small synthetic 6-DoF trace; `compare` sets frames a client saved beside the exact shading
// for the same views. docs/evaluation.md.
#include "traces/pose_trace.hpp"
#include "eval_compare.hpp"
#include "eval_report.hpp"
#include "eval_run.hpp"
#include "eval_settings.hpp"
#include "eval_trace_gen.hpp"
#include "trace/soft/soft_visibility.hpp"
#include "trace/visibility_tracer.hpp"

#include <CLI/CLI.hpp>
#include "cli/finite_range.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "plan/shipped_defaults.hpp"

int main(int argc, char** argv) {
  using namespace dhr::eval;
  CLI::App app{"dhr-eval: the DHR pipeline's run time against its error, on a virtual 90 Hz clock."};
  app.require_subcommand(1);

  RunOptions options;
  std::string rtt = "0,25,50,100,200", x_max = "all", guard = "64x36", method = "stale,paper,paper+pred";
  std::string eye_size = "160x120";
  CLI::App* run = app.add_subcommand("run", "simulate the settings over a trace and write DIR/results.{json,csv}");
  run->add_option("--scene", options.scene, "scene file (.gltf/.glb)")->required();
  run->add_option("--lights", options.lights,
                  "add point lights to the scene until it has this many (at most 256; beyond 32 they share light "
                  "slots: hard lights only, and the client has no shadow maps: local is unshadowed)")
      ->check(CLI::Range(1, 256));
  run->add_option("--light-range", options.light_range,
                  "range of the added lights, metres (default: about six reach a point; infinite up to 32 lights)")
      ->check(dhr::cli::FiniteRange(0.0, 1000.0));
  run->add_option("--trace", options.trace, "head-pose trace (any supported format, docs/traces.md)")->required();
  run->add_option("--out", options.out_dir, "output directory")->required();
  run->add_option("--rtt-ms", rtt, "round-trip times, ms (comma list)")->capture_default_str();
  run->add_option("--x-max", x_max, "frames predicted at most: integers or 'all' (comma list)")->capture_default_str();
  run->add_option("--guard", guard, "guard bands as WxH pixels at 1920x1080, or 0 (comma list)")->capture_default_str();
  run->add_option("--method", method, "default (what dhr-server and dhr-xrclient ship), stale, paper, paper+pred, local, full, "
                  "full-no-<ingredient>...[-depth-scale-N][-depth-splat][-edge-band-N] (comma list)")->capture_default_str();
  run->add_option("--frames", options.frames, "measured frames (default: the whole trace after the warm-up)");
  run->add_option("--eye-size", eye_size, "per-eye display size WxH")->capture_default_str();
  run->add_option("--trace-start", options.trace_start_s, "skip this many seconds of the trace");
  run->add_option("--jitter-ms", options.jitter_ms, "uniform jitter per direction, ms");
  run->add_option("--loss", options.loss, "datagram loss probability per direction");
  run->add_option("--server-ms", options.server_ms,
                  "modelled server compute time per traced frame (both eyes), virtual ms")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 1000.0));
  run->add_option("--seed", options.seed, "network impairment seed");
  run->add_option("--predict-window-ms", options.predict_window_ms,
                  "paper+pred: velocity from the newest pose and the oldest within this window (0: two newest)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 1000.0));
  run->add_option("--predict-max-horizon-ms", options.predict_max_horizon_ms, "paper+pred: cap of the horizon")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 2000.0));
  run->add_option("--predict-soft-horizon-ms", options.predict_soft_horizon_ms,
                  "paper+pred: horizons beyond this are damped (with --predict-damping-ms)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 2000.0));
  run->add_option("--predict-damping-ms", options.predict_damping_ms,
                  "paper+pred: damping time constant beyond the soft horizon (0: off)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 2000.0));
  run->add_option("--predict-quadratic-ms", options.predict_quadratic_ms,
                  "paper+pred: fit a quadratic (constant acceleration) to the poses of this window (0: off)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 1000.0));
  std::string codec = "v2";
  std::string render_path = "deferred";
  run->add_option("--codec", codec, "visibility codec: v2 (context-modelled, against acknowledged frames) or v1 (LZ4)")
      ->capture_default_str()
      ->check(CLI::IsMember({"v1", "v2"}));
  run->add_option("--shadow-size", options.shadow_maps.size, "local, full: shadow-map texels per cube face side")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(1u, 16384u));
  double fill_period_ms = static_cast<double>(dhr::client::shipped::kShadowFillPeriodNs) * 1e-6;
  run->add_option("--shadow-fill-period-ms", fill_period_ms,
                  "moving scenes, settings with server visibility: while the shadow maps only fill, each light's map "
                  "is re-rendered once per this much scene time, in turns (0: every frame, as local)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 10000.0));
  run->add_option("--shadow-bias-rel", options.shadow_maps.bias_rel,
                  "local, full: shadow-map depth bias per metre of distance")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 0.5));
  run->add_option("--shadow-bias-abs", options.shadow_maps.bias_abs, "local, full: shadow-map depth bias, metres")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 1.0));
  run->add_option("--shadow-normal-offset", options.shadow_maps.normal_offset,
                  "local, full: shadow lookups move this many texels along the normal")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 16.0));
  run->add_option("--shadow-bias-slope", options.shadow_maps.bias_slope,
                  "local, full: slope-scaled shadow-map bias, texels times tan(angle of normal and light)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 16.0));
  run->add_option("--plane-tolerance", options.plane_tolerance_rel,
                  "full: depth test tolerance, metres per metre of depth (plus --plane-tolerance-abs)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 1.0));
  run->add_option("--plane-tolerance-abs", options.plane_tolerance_abs, "full: depth test tolerance, metres")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 1.0));
  run->add_option("--snapshot-frame", options.snapshot_frame,
                  "write PNGs of this measured frame (0: the first) to <out>/snapshots: every setting's eyes, "
                  "the exact ones and the wrong visibility bits");
  run->add_option("--snapshot-crop", options.snapshot_crop,
                  "with --snapshot-frame: X,Y,W,H of the eye image; per round trip and guard band one picture, "
                  "snapshots/crop_rtt<R>_guard<G>_eye0.png: that crop of the exact image and of every method's, "
                  "scaled up, each method's wrong bits below")
      ->needs("--snapshot-frame");
  run->add_option("--render-path", render_path,
                  "deferred: every method and the truth on the deferred passes (images differ by visibility only); "
                  "shipped: each method on the path the client takes for it on this device (--render-path auto: "
                  "forward where it applies, unless a discrete GPU), so client_ms "
                  "is what ships (results' client_path names it); the truth is then shaded forward, so the image "
                  "metrics (SSIM, PSNR, FLIP) of methods rendered deferred also count the paths' 2/255 difference")
      ->capture_default_str()
      ->check(CLI::IsMember({"deferred", "shipped"}));
  run->add_option("--threads", options.threads, "Embree threads (0: all cores)")
      ->check(CLI::Range(0u, dhr::server::kMaxTracerThreads));
  run->add_option("--soft-first-samples", options.server_soft.initial_samples,
                  "server: first samples per pixel and light with an extent (dhr-server's default: what ships)")
      ->capture_default_str()
      ->check(CLI::Range(1u, dhr::server::kMaxSoftSamples));
  run->add_option("--soft-samples", options.server_soft.max_samples,
                  "server: samples per pixel and light with an extent where the first ones disagree")
      ->capture_default_str()
      ->check(CLI::Range(1u, dhr::server::kMaxSoftSamples));
  run->add_option("--truth-samples", options.truth_samples,
                  "ground truth: samples per pixel and light with an extent where the first ones disagree "
                  "(docs/evaluation.md, \"Soft shadows\")")
      ->capture_default_str()
      ->check(CLI::Range(1u, dhr::server::kMaxSoftSamples));
  run->add_option("--truth-first-samples", options.truth_first_samples,
                  "ground truth: the first samples, which decide where a light is seen whole or not at all "
                  "(at most --truth-samples; equal: uniform sampling)")
      ->capture_default_str()
      ->check(CLI::Range(1u, dhr::server::kMaxSoftSamples));
  bool no_progress = false;
  run->add_flag("--no-progress", no_progress, "no progress bar on stderr");

  std::string report_dir;
  CLI::App* report = app.add_subcommand("report", "plots and Markdown from a run's results");
  report->add_option("DIR", report_dir, "a directory written by `dhr-eval run`")->required();

  std::string trace_out;
  double seconds = 12.0;
  CLI::App* make_trace = app.add_subcommand("make-trace", "write a synthetic 6-DoF head trace (canonical CSV)");
  make_trace->add_option("FILE", trace_out, "output file")->required();
  make_trace->add_option("--seconds", seconds, "duration")->capture_default_str()->check(dhr::cli::FiniteRange(0.1, 3600.0));

  CompareOptions compare_options;
  CLI::App* compare = app.add_subcommand(
      "compare", "set the frames a client saved (views.jsonl + PNGs) beside the exact shading for the same views");
  compare->add_option("--scene", compare_options.scene, "the scene the client rendered (.gltf/.glb)")->required();
  compare->add_option("--shown", compare_options.shown_dir,
                      "directory of the client's PNGs and views.jsonl (dhr-xrclient --snapshot-dir or --offscreen)")
      ->required();
  compare->add_option("--out", compare_options.out_dir, "where the pictures go (default: the --shown directory)");
  compare->add_option("--tolerance", compare_options.tolerance,
                      "largest channel difference (0-255) not counted as differing")
      ->capture_default_str()
      ->check(CLI::Range(0, 255));
  compare->add_option("--threads", compare_options.threads, "Embree threads (0: all cores)")
      ->check(CLI::Range(0u, dhr::server::kMaxTracerThreads));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help (code 0) or the error
    return code == 0 ? 0 : 2;     // usage errors: 2, as dhr-server and dhr-xrclient
  }

  if (run->parsed()) {
    std::string error;
    const auto rtts = parse_rtt_list(rtt, &error);
    const auto xs = rtts ? parse_x_max_list(x_max, &error) : std::nullopt;
    const auto guards = xs ? parse_guard_list(guard, &error) : std::nullopt;
    const auto methods = guards ? parse_method_list(method, &error) : std::nullopt;
    const auto eye = parse_size(eye_size);
    if (!methods) {
      std::fprintf(stderr, "dhr-eval: %s\n", error.c_str());
      return 2;
    }
    if (!eye || eye->width < 16 || eye->height < 16 || eye->width > 4096 || eye->height > 4096) {
      std::fprintf(stderr, "dhr-eval: --eye-size: expected WxH between 16 and 4096, got '%s'\n", eye_size.c_str());
      return 2;
    }
    options.codec_v2 = codec == "v2";
    options.shadow_maps.fill_period_ns = static_cast<int64_t>(std::llround(fill_period_ms * 1e6));
    options.shipped_path = render_path == "shipped";
    if (!(options.jitter_ms >= 0.0 && options.jitter_ms <= 1000.0) || !(options.loss >= 0.0 && options.loss < 1.0)) {
      std::fprintf(stderr, "dhr-eval: --jitter-ms must be in [0, 1000] and --loss in [0, 1)\n");
      return 2;
    }
    options.rtt_ms = *rtts;
    options.x_max = *xs;
    options.guard = *guards;
    options.methods = *methods;
    options.eye = *eye;
    options.progress = !no_progress;
    std::string command_line = "dhr-eval";
    for (int i = 1; i < argc; ++i) command_line += std::string(" ") + argv[i];
    return run_eval(options, command_line);
  }
  if (report->parsed()) return write_report(report_dir);
  if (compare->parsed()) return run_compare(compare_options);
  if (make_trace->parsed()) {
    std::string error;
    if (!dhr::write_pose_trace(trace_out, synthetic_head_trace(seconds, 200.0), &error)) {
      std::fprintf(stderr, "dhr-eval: %s\n", error.c_str());
      return 1;
    }
    std::printf("dhr-eval: wrote %s (%.1f s at 200 Hz)\n", trace_out.c_str(), seconds);
    return 0;
  }
  return 2;
}
