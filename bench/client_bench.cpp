// client_bench: the per-eye GPU time of the client's ways of shading a frame, on one scene and eye size
// (docs/performance.md, "Client"). Every configuration renders frame by frame in turn (each frame submitted and
// waited for, timed with GPU timestamps), --warmup frames and then --frames measured; the median of each is
// reported. Every *_ms GPU time is per eye, the unit of forward_ms and shadowmap_ms (one eye's render): the two
// frame-loop configurations render both eyes per frame, each eye's passes timed on their own, and report the
// median over all measured eye frames (2 per frame); their host times are per eye frame as well.
//   dhr_ms           what dhr-xrclient ships (DESIGN 8b): its options without any given
//                    (plan/shipped_defaults.hpp: today `--warp edges` on the forward path, newest schedule, the
//                    scaled paper guard band), through the client's own frame loop (client_loop.hpp, both
//                    eyes): the head moves every frame and a new visibility frame per eye arrives every frame,
//                    traced for the previous frame's pose (p = 1) with Embree and coded with codec v2 against that
//                    eye's previous frame. Beside it, host times per eye frame: dhr_decode_ms (decoding that frame
//                    with the client's decoder), dhr_upload_ms (writing the visibility buffers the warp reads to
//                    host-visible GPU memory), dhr_record_ms (the frame step: planning, uploads, command
//                    recording, submission) as the thread's CPU time: its wall time, dhr_record_wall_ms, also
//                    counts the time slices a shared machine's other processes and lavapipe's own threads take
//                    from the thread, which on 2 cores decide its median. One GPU slot instead of the client's
//                    two, so that each frame can be waited for and interleaved with the others.
//   dhr_full_ms      the same with `--warp full`: the traced camera's depth is rendered every frame, the warp also
//                    reads the other eye's buffer, the eye's previous one and the shadow maps; dhr_full_decode_ms,
//                    dhr_full_upload_ms, dhr_full_record_ms as above. dhr_ms is the shipped warp (today
//                    `--warp edges`).
//   dhr_edges_depthN_ms  (--depth-scales N,..., default the shipped --depth-scale) `--warp edges-depth
//                    --depth-scale N`: `--warp edges` plus the depth test against the traced camera's depth rendered
//                    at 1/N resolution every frame; keys as above, _vs_forward and _added_vs_shadowmap_added its
//                    ratios against the goals. With the shipped `--warp edges`, dhr_shadow_frac is the median
//                    fraction of surface pixels that looked up the shadow maps.
//   dhr_edges_ms     (--edges) `--warp edges`: no depth test (what `--warp auto` takes where every light is hard);
//                    keys as dhr_ms.
//   dhr_edges_splatN_ms  (--splat-scales N,...) `--warp edges-depth --traced-depth splat --depth-scale N`: the depth
//                    test against the traced depth moved from the eye's previous frame (one compute pass, no raster;
//                    render/traced_depth_splat.hpp); keys as dhr_edges_depthN_ms.
//   dhr_edge_bandN_ms  (--edge-bands N,...) the shipped client with `--edge-band N` (0: the shadow maps only where
//                    the 2x2 samples disagree); keys as dhr_ms. dhr_edge_marks_ms: the host time of the edge band's
//                    marks per eye frame (render/warp_edges.hpp), computed with each buffer's upload over the hard
//                    fields' bits, as the warp passes do (null where they make none: band 0, or no hard light).
//   dhr_alt_path_ms  (--alt-path) the shipped client on the other render path: the deferred passes (G-buffer, compute
//                    warp, compute shading) where `--render-path auto` takes the forward pass on this device (not a
//                    discrete GPU), the forward pass where it takes the deferred ones; keys as dhr_ms.
//                    dhr_render_path_rule: the shipped --render-path (plan/render_path.hpp)
//   dhr_levels_ms    (--levels) the shipped client with its soft fields shaded at their levels, without the warp's
//                    refined shares (WarpSettings::soft_refine off); keys as dhr_ms. shadow_map_size: the maps'
//                    texels per face side (--shadow-size, local's and the loops' alike)
//   dhr_paper_static_ms  the paper's warp on the forward path, one eye at a fixed view with a fixed visibility
//                    buffer (render::EyePipeline directly): the warp and shading alone, no frame loop
//   dhr_deferred_ms  the same rule in the deferred passes (G-buffer -> warp -> shading; the client before issue 15),
//                    same fixed view and buffer
//   forward_ms       a plain forward Lambert render without shadows (the cost of not having shadows)
//   shadowmap_ms     a forward render with the client's cube shadow maps (what a headset would do without DHR;
//                    the maps are rendered once, as for a static scene: shadow_map_render_ms is that host time).
//                    Lights with an extent take PCSS (shaders/client/pcss.h): shadowmap_soft_lights counts them
//                    (0: every lookup is the hard one-texel test), shadowmap_pcss_taps gives the blocker-search and
//                    filter taps per soft light and pixel
//   shadowmap_hard_ms (scenes with soft lights) the same render with every light's lookup hard (extents dropped,
//                    the same maps): shadowmap_ms - shadowmap_hard_ms is the soft shadows' cost
// A scene that moves (glTF animations; scene_moves) is rendered at each frame's scene time (90 Hz from 0) by every
// configuration. `local` then re-renders, per frame and before its eye's render, the shadow-map faces moving
// casters or lights made stale (render::ShadowMaps::update, the rule in xrclient/render/shadow_refresh.hpp):
// shadowmap_update_ms (GPU, per frame: both eyes share the maps), shadowmap_update_lights / _faces (medians per
// frame), shadowmap_moving_ms = shadowmap_ms + shadowmap_update_ms / 2 (local per eye with its share of the
// re-render); the frame loops report the same as dhr_shadow_update_ms / dhr_shadow_update_lights (their maps fill
// the warp's undecided bits; where they only fill, the lights take turns, --shadow-fill-period-ms, so the loops also
// give dhr_shadow_update_mean_ms / _max_ms / _mean_lights, and local shadowmap_update_mean_ms / _max_ms).
// All 0 for a static scene. dhr_paper_static_ms and dhr_deferred_ms draw it at rest.
// Against the cost goal: dhr_vs_forward (<= 1.3) and dhr_added_vs_shadowmap_added = (dhr_ms - forward_ms) /
// (shadowmap_ms - forward_ms) (<= 0.5). The fixed view is the scene's first bookmark; the fixed visibility buffer
// is the server's Embree trace for the pose one 90 Hz frame earlier (turning 60 deg/s). --lights N above the
// scene's count adds point lights (copies of the scene's point lights, moved by a fixed pattern) so the light
// count can be swept; beyond 32, trace_bench's bench lights, which share light slots (client_bench_many.hpp: no
// `local`, DHR's deferred path against the forward render clustered by the slots). Progress on stderr; the last
// stdout line is one JSON object.
#include <CLI/CLI.hpp>
#include "cli/finite_range.hpp"
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_lights.hpp"
#include "bench_timing.hpp"
#include "client_bench_configs.hpp"
#include "client_bench_many.hpp"
#include "bench_views.hpp"
#include "client_loop.hpp"
#include "cli/exit_codes.hpp"
#include "coded_visibility_source.hpp"
#include "frame/frame_coordinator.hpp"
#include "plan/shipped_defaults.hpp"
#include "scene/camera_bookmarks.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/forward_pass.hpp"
#include "render/render_camera.hpp"
#include "render/light_layout.hpp"
#include "render/pcss_reference.hpp"
#include "render/shadow_maps.hpp"
#include "scene/scene.hpp"
#include "vk/buffer.hpp"
#include "vk/context.hpp"
#include "vk/timestamps.hpp"

namespace dhr::bench {
namespace {

struct Options {
  std::string scene;
  std::string size = "320x240";
  uint32_t lights = 0;  // 0: the scene's
  uint32_t frames = 30;
  uint32_t warmup = 5;
  bool skip_full = false;
  bool alt_path = false;  // also the shipped client on the other render path (dhr_alt_path_ms)
  uint32_t scene_lag = 0;  // frames of scene motion between a buffer's traced scene time and its display
  std::vector<uint32_t> depth_scales{client::shipped::kDepthScale};  // --warp edges-depth at these (dhr_edges_depthN_ms)
  std::vector<uint32_t> edge_bands;  // the shipped client with these --edge-band values too (dhr_edge_bandN_ms)
  bool edges = false;  // --edges: `--warp edges` too (dhr_edges_ms; what --warp auto takes where every light is hard)
  std::vector<uint32_t> splat_scales;  // --warp edges-depth --traced-depth splat at these (dhr_edges_splatN_ms)
  // the frame loops' maps in a moving scene (render::ShadowMapSettings::fill_period_ns), milliseconds
  double fill_period_ms = static_cast<double>(render::ShadowMapSettings{}.fill_period_ns) * 1e-6;
  uint32_t shadow_size = render::ShadowMapSettings{}.size;  // texels per face side: `local`'s maps and the loops'
  bool levels = false;  // --levels: the shipped client without refined soft shares too (dhr_levels_ms)
};

int run(const Options& o) {
  const std::optional<Extent> size = parse_size(o.size);
  if (!size) throw cli::InputError("--size: expected WxH with 1..8192 per axis, got '" + o.size + "'");
  const SceneLoadResult loaded = load_scene(o.scene);
  if (!loaded) throw cli::InputError(loaded.error);  // names the file
  Scene scene = *loaded.scene;
  if (o.lights > kMaxSlotLights) throw cli::InputError("--lights: at most 256");
  // Beyond 32 lights: the bench lights of trace_bench and codec_bench (they share light slots).
  if (o.lights > kMaxLights) add_bench_lights(scene, o.lights, default_bench_light_range(scene, o.lights));
  if (o.lights > scene.lights.size()) add_lights(scene, o.lights);
  if (o.lights > 0 && o.lights < scene.lights.size()) scene.lights.resize(o.lights);
  const uint32_t light_count = static_cast<uint32_t>(scene.lights.size());
  if (light_count == 0) throw std::runtime_error("the scene has no light");

  std::string note;
  const std::vector<CameraBookmark> bookmarks = bench_bookmarks(o.scene, scene, note);
  const std::optional<Pose> head = look_at_pose(bookmarks.at(0));
  if (!head) throw std::runtime_error("the scene's first camera bookmark has no usable pose");
  View view;
  view.pose = *head;
  view.fov = symmetric_fov(kTraceBenchFovDegrees, *size);
  // The pose the server traced: one 90 Hz frame earlier, the head turning at 60 degrees per second.
  View traced_view = view;
  traced_view.pose.orientation =
      glm::normalize(glm::angleAxis(glm::radians(60.0 / 90.0), glm::dvec3(0.0, 1.0, 0.0)) * view.pose.orientation);
  const GuardBand guard = bench_guard_band(*size);
  const Camera traced = Camera::with_guard_band(traced_view, *size, guard);

  std::fprintf(stderr, "client_bench: %s, %ux%u per eye, %u lights: tracing the server's buffer (Embree)\n",
               o.scene.c_str(), size->width, size->height, light_count);
  server::TracerOptions tracer_options;
  server::EmbreeTracer tracer(scene, tracer_options);
  VisibilityBuffer buffer;
  server::TraceStats trace_stats;
  tracer.trace(traced, buffer, trace_stats);
  VisibilityInput input;
  input.buffer = &buffer;
  input.traced = traced;
  input.key = 1;  // uploaded once
  if (light_count > kMaxLights) return run_many_lights(o.scene, scene, *size, view, input, o.warmup, o.frames);

  vk::ContextOptions vk_options;
  vk_options.app_name = "client_bench";
  const std::unique_ptr<vk::Context> context = vk::Context::create(vk_options);
  const render::ClientScene gpu_scene(*context, scene);
  const auto maps_start = std::chrono::steady_clock::now();
  render::ShadowMapSettings map_settings;
  map_settings.size = o.shadow_size;
  render::ShadowMaps maps(*context, gpu_scene, map_settings);
  const double maps_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - maps_start).count();
  const Camera display = render::display_camera(view, *size);

  nlohmann::ordered_json out;
  out["bench"] = "client_bench";
  out["scene"] = std::filesystem::path(o.scene).filename().string();
  out["size"] = std::to_string(size->width) + "x" + std::to_string(size->height);
  out["lights"] = light_count;
  {
    const VisibilityLayout layout = render::layout_for_lights(scene.lights);
    uint32_t soft = 0;
    for (uint32_t i = 0; i < layout.light_count; ++i) soft += layout.is_soft(i) ? 1u : 0u;
    const render::PcssTaps taps = render::pcss_taps();
    out["shadowmap_soft_lights"] = soft;
    out["shadowmap_pcss_taps"] = {{"search", taps.search}, {"filter", taps.filter}};
  }
  out["device"] = context->info().name;
  out["scene_moves"] = gpu_scene.motion().animated();
  out["frames"] = o.frames;
  out["scene_lag"] = o.scene_lag;

  // The frame loops first: the shipped client, then `--warp full` and `--warp edges`.
  std::vector<Config> configs;
  std::vector<std::unique_ptr<ClientLoop>> loops;
  const auto add_loop = [&](const char* name, client::CoordinatorOptions options) {
    options.shadow_maps.size = o.shadow_size;
    options.shadow_maps.fill_period_ns = static_cast<int64_t>(std::llround(o.fill_period_ms * 1e6));
    const TracedFormat format{*size, client::shipped::guard_band(*size)};
    // Visibility is shown one frame after its pose: traced for the scene time it is shown at, unless --scene-lag.
    const int64_t lead_ns = (1 - static_cast<int64_t>(o.scene_lag)) * frame_time_ns(1);
    loops.push_back(std::make_unique<ClientLoop>(name, *context, gpu_scene, *size, tracer, format, options, *head,
                                                 view.fov, o.warmup + o.frames, lead_ns));
    ClientLoop* loop = loops.back().get();
    configs.push_back(Config{std::string(name) + "_ms", [loop, &o](uint32_t i) { return loop->run(i, o.warmup); }, {}});
  };
  const bool discrete_gpu = context->info().is_discrete_gpu;  // the shipped render path's rule
  const bool soft_scene = scene.has_soft_lights();              // the shipped warp's rule (--warp auto)
  out["dhr_render_path_rule"] = client::to_string(client::shipped::kRenderPath);
  add_loop("dhr", shipped_options(discrete_gpu, soft_scene));
  if (!o.skip_full) {
    client::CoordinatorOptions full = shipped_options(discrete_gpu, soft_scene);
    full.eye.warp = render::WarpSettings::full();
    add_loop("dhr_full", full);
  }
  if (o.alt_path) {
    client::CoordinatorOptions alt = shipped_options(discrete_gpu, soft_scene);
    alt.eye.forward = !alt.eye.forward;
    add_loop("dhr_alt_path", alt);
  }
  if (o.levels) {
    client::CoordinatorOptions levels = shipped_options(discrete_gpu, soft_scene);
    levels.eye.warp.soft_refine = false;
    add_loop("dhr_levels", levels);
  }
  std::vector<std::string> scale_names;
  if (o.edges) {
    client::CoordinatorOptions edges = shipped_options(discrete_gpu, soft_scene);
    edges.eye.warp = render::WarpSettings::server_edges();
    scale_names.push_back("dhr_edges");
    add_loop("dhr_edges", edges);
  }
  for (const uint32_t scale : o.depth_scales) {
    client::CoordinatorOptions edges = shipped_options(discrete_gpu, soft_scene);
    edges.eye.warp = render::WarpSettings::server_edges_depth(scale);
    scale_names.push_back("dhr_edges_depth" + std::to_string(scale));
    add_loop(scale_names.back().c_str(), edges);
  }
  for (const uint32_t scale : o.splat_scales) {
    client::CoordinatorOptions edges = shipped_options(discrete_gpu, soft_scene);
    edges.eye.warp = render::warp_settings_for(client::WarpChoice::kEdgesDepth, scale, client::shipped::kEdgeBand,
                                               client::TracedDepth::kSplat);
    scale_names.push_back("dhr_edges_splat" + std::to_string(scale));
    add_loop(scale_names.back().c_str(), edges);
  }
  for (const uint32_t band : o.edge_bands) {
    client::CoordinatorOptions banded = shipped_options(discrete_gpu, soft_scene);
    banded.eye.warp.edge_band = band;
    scale_names.push_back("dhr_edge_band" + std::to_string(band));
    add_loop(scale_names.back().c_str(), banded);
  }

  // The paper's warp and its deferred twin, one eye each at the fixed view.
  std::vector<std::unique_ptr<render::EyePipeline>> eyes;
  std::vector<render::EyeStats> eye_stats;
  const auto add_eye = [&](const char* name, const render::EyePipelineOptions& options) {
    const size_t k = eyes.size();
    eyes.push_back(std::make_unique<render::EyePipeline>(*context, gpu_scene, *size, options));
    eye_stats.emplace_back();
    configs.push_back(single_eye_config(
        *context, name,
        [&, k](VkCommandBuffer cmd, uint32_t) {
          eyes[k]->prepare(cmd, 0, input);
          eyes[k]->record(cmd, 0, view, input);
        },
        [&, k]() -> std::optional<double> {
          eye_stats[k] = eyes[k]->read_stats(0);
          if (!eye_stats[k].gpu.valid) return std::nullopt;
          return eye_stats[k].gpu.total_ms;
        }));
  };
  render::EyePipelineOptions paper;  // the defaults: the paper's warp, the forward path
  paper.frames_in_flight = 1;
  add_eye("dhr_paper_static_ms", paper);
  render::EyePipelineOptions deferred = paper;
  deferred.forward = false;
  add_eye("dhr_deferred_ms", deferred);

  // The forward baselines.
  std::vector<std::unique_ptr<render::ForwardPass>> passes;
  std::vector<render::ForwardTargets> targets;
  std::vector<std::unique_ptr<vk::TimestampQueries>> stamps;
  render::ForwardFrame frame;
  frame.display = display;
  frame.lights = scene.lights;
  frame.shadow_maps = &maps;
  // With soft lights, the same shadow-map render with every lookup hard (the lights' extents dropped; the same
  // maps): shadowmap_ms - shadowmap_hard_ms is what PCSS costs.
  std::vector<SceneLight> hard_lights = scene.lights;
  for (SceneLight& l : hard_lights) l.radius = l.angle = l.width = l.height = 0.0f;
  render::ForwardFrame hard_frame = frame;
  hard_frame.lights = hard_lights;
  struct Baseline {
    const char* name;
    render::ForwardMode mode;
    const render::ForwardFrame* frame;
    bool hard = false;         // the lights' extents dropped
    bool updates_maps = false; // a moving scene: re-renders the stale shadow-map faces first (local)
  };
  std::vector<Baseline> baselines = {{"forward_ms", render::ForwardMode::kLambert, &frame},
                                     {"shadowmap_ms", render::ForwardMode::kShadowMaps, &frame, false, true}};
  if (out["shadowmap_soft_lights"].get<uint32_t>() > 0) {
    baselines.push_back({"shadowmap_hard_ms", render::ForwardMode::kShadowMaps, &hard_frame, true});
  }
  // A moving scene: each baseline renders it at frame i's scene time; `local` re-renders its stale maps per frame.
  const bool scene_moves = gpu_scene.motion().animated();
  render::MovedScene moved;
  std::vector<SceneLight> moved_hard_lights;
  vk::TimestampQueries update_stamps(*context, 2);
  render::ShadowUpdate last_update;
  std::vector<double> update_ms, update_lights, update_faces;  // per frame, warm-up included
  for (const Baseline& b : baselines) {
    render::ForwardOptions fo;
    fo.mode = b.mode;
    const size_t k = passes.size();
    passes.push_back(std::make_unique<render::ForwardPass>(*context, gpu_scene, fo));
    targets.push_back(render::ForwardTargets::create(*context, *size, fo));
    stamps.push_back(std::make_unique<vk::TimestampQueries>(*context, 2));
    configs.push_back(single_eye_config(
        *context, b.name,
        [&, k, b](VkCommandBuffer cmd, uint32_t i) {
          render::ForwardFrame f = *b.frame;
          if (scene_moves) {
            gpu_scene.motion().sample(render::scene_seconds(frame_time_ns(i)), gpu_scene.meshes(), moved);
            f.moved = &moved;
            f.lights = moved.lights;
            if (b.hard) {
              moved_hard_lights = moved.lights;
              for (SceneLight& l : moved_hard_lights) l.radius = l.angle = l.width = l.height = 0.0f;
              f.lights = moved_hard_lights;
            }
            if (b.updates_maps) {
              update_stamps.reset(cmd);
              update_stamps.write(cmd, 0);
              last_update = maps.update(cmd, moved);
              update_stamps.write(cmd, 1);
            }
          }
          stamps[k]->reset(cmd);
          stamps[k]->write(cmd, 0);
          passes[k]->record(cmd, 0, f, targets[k]);
          stamps[k]->write(cmd, 1);
        },
        [&, k, b]() -> std::optional<double> {
          if (scene_moves && b.updates_maps) {
            const std::vector<double> uns = update_stamps.read_ns();
            update_ms.push_back(uns.size() == 2 && last_update.faces > 0 ? (uns[1] - uns[0]) * 1e-6 : 0.0);
            update_lights.push_back(last_update.lights);
            update_faces.push_back(last_update.faces);
          }
          const std::vector<double> ns = stamps[k]->read_ns();
          if (ns.size() != 2) return std::nullopt;
          return (ns[1] - ns[0]) * 1e-6;
        }));
  }
  std::fprintf(stderr, "client_bench: %zu configurations, %u + %u frames each\n", configs.size(), o.warmup, o.frames);
  measure(o.warmup, o.frames, configs);
  for (const Config& c : configs) {
    if (c.samples.empty()) throw std::runtime_error("no GPU timestamps on " + context->info().name + ": nothing to measure");
    out[c.name] = median(c.samples, std::nan(""));
  }
  for (const std::unique_ptr<ClientLoop>& loop : loops) loop->report(out);
  const render::EyeStats& paper_stats = eye_stats[0];
  out["dhr_paper_static_path"] = paper_stats.forward ? "forward" : "deferred";
  out["shadow_map_render_ms"] = maps_ms;
  out["shadow_map_size"] = maps.face_size();
  {
    const auto kept = [&](const std::vector<double>& v) {
      return median(std::vector<double>(v.begin() + std::min<size_t>(v.size(), o.warmup), v.end()), 0.0);
    };
    out["shadowmap_update_ms"] = kept(update_ms);
    const std::vector<double> kept_ms(update_ms.begin() + std::min<size_t>(update_ms.size(), o.warmup),
                                      update_ms.end());
    out["shadowmap_update_mean_ms"] = mean(kept_ms, 0.0);
    out["shadowmap_update_max_ms"] = largest(kept_ms, 0.0);
    out["shadowmap_update_lights"] = kept(update_lights);
    out["shadowmap_update_faces"] = kept(update_faces);
    out["shadowmap_moving_ms"] = out["shadowmap_ms"].get<double>() + kept(update_ms) / 2.0;
  }
  const double forward = out["forward_ms"].get<double>();
  const double shadowmap = out["shadowmap_ms"].get<double>();
  const double dhr = out["dhr_ms"].get<double>();
  // The cost goal (issue 25): dhr_vs_forward <= 1.3 and dhr_added_vs_shadowmap_added <= 0.5.
  out["dhr_vs_forward"] = dhr / forward;
  out["dhr_added_vs_shadowmap_added"] = (dhr - forward) / (shadowmap - forward);
  if (!o.skip_full) out["dhr_full_vs_forward"] = out["dhr_full_ms"].get<double>() / forward;
  if (o.alt_path) out["dhr_alt_path_vs_forward"] = out["dhr_alt_path_ms"].get<double>() / forward;
  for (const std::string& name : scale_names) {
    const double ms = out[name + "_ms"].get<double>();
    out[name + "_vs_forward"] = ms / forward;
    out[name + "_added_vs_shadowmap_added"] = (ms - forward) / (shadowmap - forward);
  }
  out["dhr_paper_static_vs_forward"] = out["dhr_paper_static_ms"].get<double>() / forward;
  out["dhr_deferred_vs_forward"] = out["dhr_deferred_ms"].get<double>() / forward;
  out["shadowmap_vs_forward"] = shadowmap / forward;
  out["triangles_drawn"] = paper_stats.draws.triangles_drawn;  // at the fixed view
  out["dhr_paper_static_known_frac"] =
      paper_stats.warp.surface() == 0 ? 0.0
                                      : static_cast<double>(paper_stats.warp[render::WarpStatus::kKnown]) /
                                            static_cast<double>(paper_stats.warp.surface());
  std::printf("%s\n", out.dump().c_str());
  return 0;
}

}  // namespace
}  // namespace dhr::bench

int main(int argc, char** argv) {
  dhr::bench::Options o;
  o.scene = std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room.gltf";
  CLI::App app{"client_bench: per-eye GPU time of the DHR client against forward renders without shadows and with "
               "shadow maps (docs/performance.md). The last stdout line is one JSON object."};
  app.add_option("--scene", o.scene, "glTF scene")->capture_default_str();
  app.add_option("--size", o.size, "eye size WxH")->capture_default_str();
  app.add_option("--lights", o.lights, "light count: fewer than the scene's drops lights, more adds copies of its point "
                                       "lights, beyond 32 the bench lights of trace_bench (light slots: no local, "
                                       "DHR deferred against clustered forward; at most 256) (0: the scene's)")
      ->capture_default_str();
  app.add_option("--frames", o.frames, "measured frames per configuration (median)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(1u, 100000u));
  app.add_option("--warmup", o.warmup, "unmeasured frames first")->capture_default_str();
  app.add_flag("--skip-full", o.skip_full, "do not measure --warp full (dhr_full_ms)");
  app.add_flag("--alt-path", o.alt_path,
               "also measure the shipped client on the render path --render-path auto does not take on this device "
               "(deferred where it takes the forward pass, and the reverse: dhr_alt_path_ms, dhr_alt_path_path)");
  app.add_option("--scene-lag", o.scene_lag,
                 "a moving scene: frames between the scene time visibility is traced for and the one it is shown at "
                 "(0: a server that predicted the display exactly; 1: one frame of motion for the warp's motion rule)")
      ->check(CLI::Range(0u, 1u))
      ->capture_default_str();
  app.add_option("--depth-scales", o.depth_scales,
                 "also measure --warp edges-depth with the traced depth at each of these scales (dhr_edges_depthN_ms)")
      ->capture_default_str()
      ->delimiter(',')
      ->check(CLI::Range(1u, 16u));
  app.add_flag("--edges", o.edges,
               "also measure --warp edges (dhr_edges_ms: what --warp auto ships where every light is hard)");
  app.add_option("--splat-scales", o.splat_scales,
                 "also measure --warp edges-depth --traced-depth splat with the traced depth at each of these scales "
                 "(dhr_edges_splatN_ms)")
      ->delimiter(',')
      ->check(CLI::Range(1u, 16u));
  app.add_option("--edge-bands", o.edge_bands,
                 "also measure the shipped client with each of these --edge-band values (dhr_edge_bandN_ms)")
      ->delimiter(',')
      ->check(CLI::Range(0u, 8u));
  app.add_flag("--levels", o.levels,
               "also measure the shipped client with its soft fields shaded at their levels, without the warp's "
               "refined shares (dhr_levels_ms)");
  app.add_option("--shadow-size", o.shadow_size,
                 "shadow-map texels per cube face side, for local's maps and the frame loops' (shadow_map_size)")
      ->capture_default_str()
      ->check(CLI::Range(16u, 4096u));
  app.add_option("--shadow-fill-period-ms", o.fill_period_ms,
                 "moving scenes: while the frame loops' shadow maps only fill, each light's map is re-rendered once "
                 "per this much scene time, in turns (0: every frame, as local's)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 10000.0));
  bool quick = false;
  app.add_flag("--quick", quick, "smoke run: 64x48, 2 frames after 1 warm-up (unless given)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "client_bench: %s (--help lists the options)\n", e.what());
    return 2;
  }
  if (quick) {
    if (app.count("--size") == 0) o.size = "64x48";
    if (app.count("--frames") == 0) o.frames = 2;
    if (app.count("--warmup") == 0) o.warmup = 1;
  }
  try {
    return dhr::bench::run(o);
  } catch (const dhr::cli::InputError& e) {
    std::fprintf(stderr, "client_bench: %s\n", e.what());
    return dhr::exit_code::kUsage;
  } catch (const std::exception& e) {  // Vulkan, a failed frame: the measurement failed
    std::fprintf(stderr, "client_bench: %s\n", e.what());
    return dhr::exit_code::kFailure;
  }
}
