#include "app/client_setup.hpp"

#include "render/light_layout.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>

#include "app/run_modes.hpp"
#include "log/log.hpp"
#include "net/peer_address.hpp"
#include "scene/session_scene.hpp"

namespace dhr::client {

Scene load_client_scene(const ClientOptions& options) {
  std::string error;
  std::optional<Scene> scene = load_session_scene(options.scene, options.lights, &error);
  if (!scene) throw InputError("cannot load scene: " + error);
  for (const std::string& w : scene->warnings) log::warn("scene: %s", w.c_str());
  log::info("scene: %s", scene_summary(*scene).c_str());
  return std::move(*scene);
}

std::unique_ptr<NodeScriptPlayer> load_node_script_player(const ClientOptions& options, const Scene& scene) {
  if (options.node_script.empty()) return nullptr;
  std::string error;
  std::optional<std::vector<NodeScriptStep>> steps = load_node_script(options.node_script, scene, &error);
  if (!steps) throw InputError("--node-script " + error);
  log::info("node script: %zu transforms from %s", steps->size(), options.node_script.c_str());
  return std::make_unique<NodeScriptPlayer>(std::move(*steps), scene);
}

std::unique_ptr<UdpVisibilityClient> connect_to_server(const ClientOptions& options, Extent eye, GuardBand guard,
                                                       uint64_t scene_hash, const render::ClientScene& scene) {
  std::string host;
  uint16_t port = 0;
  if (!net::split_host_port(options.server, host, port)) {
    throw InputError("--server: expected HOST:PORT, got '" + options.server + "'");
  }
  VisibilityClientConfig config;
  if (!options.key_file.empty()) {
    std::string error;
    config.key = secure::load_key_file(options.key_file, &error);
    if (!config.key) throw InputError("--key-file: " + error);
  }
  config.scene_hash = scene_hash;
  // The fields the server sends: one per light, or the light slots both ends derive (a soft mask of the fields).
  config.soft_lights = render::soft_light_mask(render::layout_for_lights(scene.field_lights()));
  config.light_slots = scene.light_slots().is_identity() ? 0u : scene.light_slots().slot_count();
  config.format = TracedFormat{eye, guard};
  config.codec_v2 = options.codec_v2;
  config.hello_give_up_ns = static_cast<int64_t>(options.connect_timeout_s * 1e9);
  // --warp full and edges have the client's own shadow maps to show: they never give up on the server (offline
  // mode).
  config.keep_retrying = options.warp != WarpChoice::kPaper;
  auto link = std::make_unique<UdpVisibilityClient>();
  link->connect(config, host, port, options.impairment);
  // Setup, not the frame loop: waiting for the handshake here keeps the first frames meaningful.
  const auto start = std::chrono::steady_clock::now();
  while (true) {
    link->client().tick();
    if (link->client().connected()) break;
    if (link->client().failed()) {
      if (link->client().failed_authentication()) {
        throw AuthenticationError("dhr-server at " + options.server + ": " + link->client().failure());
      }
      if (link->client().failure_kind() == ClientFailure::kSceneMismatch) {
        throw SceneMismatchError("dhr-server at " + options.server + ": " + link->client().failure());
      }
      throw std::runtime_error("no dhr-server reachable at " + options.server + ": " + link->client().failure());
    }
    if (config.keep_retrying &&
        std::chrono::steady_clock::now() - start >= std::chrono::duration<double>(options.connect_timeout_s)) {
      log::warn("no dhr-server at %s yet: shading with the client's shadow maps, still trying",
                options.server.c_str());
      return link;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const Welcome w = *link->client().welcome();
  log::info("connected to %s: %ux%u per eye traced (guard %u,%u per side), %u lights", options.server.c_str(),
            w.buffer_width, w.buffer_height, w.guard_x, w.guard_y, w.light_count);
  if (options.view == "light" && options.view_light >= w.light_count) {
    throw std::runtime_error("--view light:" + std::to_string(options.view_light) + ": the server traces " +
                             std::to_string(w.light_count) + " lights: N must be below that");
  }
  return link;
}

std::string summary_json(const RunSummary& run, const ClientOptions& options, const FrameSummary& frames,
                         const UdpVisibilityClient& link) {
  const ClientNetStats net = link.client().stats();
  const net::UdpCounters udp = link.udp_counters();
  nlohmann::ordered_json j;
  j["frames"] = run.frames;
  j["fps"] = run.fps;
  const auto opt = [](std::optional<double> v) { return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(); };
  j["response_ms_median"] = opt(frames.response_ms_median());
  j["bits_per_frame"] = run.frames > 0 ? 8.0 * static_cast<double>(udp.bytes_received) / static_cast<double>(run.frames)
                                       : 0.0;
  j["predicted_frac"] = frames.predicted_frac();
  j["unknown_frac"] = frames.unknown_frac();
  j["mode"] = run.mode;
  j["exit"] = run.exit;
  j["pose_source"] = run.pose_source;
  j["elapsed_s"] = run.elapsed_s;
  j["eye_size"] = {run.eye.width, run.eye.height};
  j["render_scale"] = run.render_scale;
  j["guard"] = {2 * run.guard.x, 2 * run.guard.y};  // both sides together, as --guard
  if (const auto w = link.client().welcome()) {
    j["buffer_size"] = {w->buffer_width, w->buffer_height};
    j["lights"] = w->light_count;
    j["codec"] = (w->capabilities & kCapabilityCodecV2) ? "v2" : "v1";
  }
  j["schedule"] = schedule_name(options.schedule);
  j["x_max"] = options.x_max;
  j["view"] = view_name(options);
  // --render-path as given, and the passes most eye frames took (auto decides by the device: plan/render_path.hpp):
  // a frame on the forward pass times no G-buffer, one on the deferred passes no forward pass.
  j["render_path"] = to_string(options.render_path);
  const bool forward = frames.forward_ms_median().value_or(0.0) > 0.0,
             deferred = frames.gbuffer_ms_median().value_or(0.0) > 0.0;
  j["render_passes"] = forward == deferred ? nlohmann::ordered_json() : forward ? "forward" : "deferred";
  j["frames_with_visibility"] = frames.frames_with_visibility();
  j["frames_local"] = frames.frames_local();
  j["reconnects"] = net.sessions_restarted;
  j["pixels_shadow_map"] = frames.pixels_shadow_map();
  j["pixels_other_eye"] = frames.pixels_other_eye();
  j["pixels_older"] = frames.pixels_older();
  j["pixels_neighbour"] = frames.pixels_neighbour();
  j["age_frames_median"] = opt(frames.age_median());
  j["responses"] = frames.responses();
  j["gbuffer_ms_median"] = opt(frames.gbuffer_ms_median());
  j["warp_ms_median"] = opt(frames.warp_ms_median());
  j["shading_ms_median"] = opt(frames.shading_ms_median());
  j["forward_ms_median"] = opt(frames.forward_ms_median());
  j["eye_gpu_ms_median"] = opt(frames.eye_gpu_ms_median());
  j["shadow_update_ms_median"] = opt(frames.shadow_update_ms_median());
  j["poses_rejected"] = run.poses_rejected;
  j["png_files"] = run.png_files;
  j["net"] = {{"poses_sent", net.poses_sent},
              {"bytes_received", udp.bytes_received},
              {"frames_completed", net.frames_completed},
              {"frames_published_partial", net.frames_published_partial},
              {"server_datagrams_missing", net.server_datagrams_missing},
              {"hellos_sent", net.hellos_sent},
              {"hellos_backed_off", net.hellos_backed_off},
              {"sessions_restarted", net.sessions_restarted},
              {"impairment", options.impairment.describe()}};
  return j.dump();
}

PoseGuard make_pose_guard(const EyeModel& eyes) {
  return PoseGuard(eyes.views(Pose{glm::dvec3(0.0, kDefaultEyeHeightMetres, 0.0), glm::dquat(1, 0, 0, 0)}));
}

FrameInput frame_input(const FramePose& sample, PoseGuard& guard) {
  FrameInput input;
  input.pose = sample;
  input.pose_reused = guard.filter(sample.frame, input.pose.views);
  return input;
}

CoordinatorOptions coordinator_options(const ClientOptions& options, bool discrete_gpu, bool scene_has_soft_lights) {
  using render::ShadingView;
  CoordinatorOptions out;
  out.plan.schedule = options.schedule;
  out.plan.x_max = options.x_max;
  const std::pair<const char*, ShadingView> views[] = {
      {"shaded", ShadingView::kShaded}, {"light", ShadingView::kLightVisibility}, {"unknown", ShadingView::kUnknown},
      {"motion", ShadingView::kMotion}, {"albedo", ShadingView::kAlbedo},         {"normal", ShadingView::kNormal}};
  for (const auto& [name, view] : views) {
    if (options.view == name) out.eye.shading.view = view;
  }
  out.eye.shading.debug_light = options.view_light;
  const render::WarpOutputs needed = render::warp_outputs_for(out.eye.shading.view);
  out.eye.warp_status = needed.status;
  out.eye.warp = render::warp_settings_for(resolve_warp(options.warp, scene_has_soft_lights), options.depth_scale,
                                           options.edge_band, options.traced_depth);
  out.eye.forward = forward_pass_for(options.render_path, discrete_gpu);
  out.eye.motion_vectors = needed.motion;
  out.shadow_maps.fill_period_ns = static_cast<int64_t>(std::llround(options.shadow_fill_period_ms * 1e6));
  return out;
}

std::string view_name(const ClientOptions& options) {
  return options.view == "light" ? "light:" + std::to_string(options.view_light) : options.view;
}

void describe_pictures(PngSink& png, const FrameCoordinator& coordinator, const ClientOptions& options,
                       bool scene_has_soft_lights) {
  // The warp that ran: --warp auto resolved for the scene.
  png.describe(coordinator, to_string(resolve_warp(options.warp, scene_has_soft_lights)), view_name(options));
}

void note_source_failure(const VisibilitySource& source, bool& warned) {
  if (warned || !source.failed()) return;
  log::error("network: %s; rendering on with the last visibility", source.failure().c_str());
  warned = true;
}

int finish_run(const RunSummary& run, const ClientOptions& options, const FrameSummary& frames,
               UdpVisibilityClient& link) {
  const std::string summary = summary_json(run, options, frames, link);
  link.close();
  std::fflush(stderr);
  std::printf("%s\n", summary.c_str());
  std::fflush(stdout);
  if (run.exit == "clean") return kExitOk;
  return run.exit == kExitScene ? kExitSceneMismatch : kExitNotClean;
}

bool scene_mismatch(const UdpVisibilityClient& link) {
  return link.client().failure_kind() == ClientFailure::kSceneMismatch;
}

}  // namespace dhr::client
