#include "serve_command.hpp"

#include "layout_report.hpp"
#include "scene_setup.hpp"
#include "scene/scene_hash.hpp"
#include "scene/session_scene.hpp"
#include "session/serve.hpp"
#include "session/shipped_defaults.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace dhr::server::cli {
int run_serve_command(const ServerOptions& options) {
  std::string error;
  std::optional<secure::Key> key;
  if (!options.key_file.empty()) {
    key = secure::load_key_file(options.key_file, &error);
    if (!key) return fail_setup(error);
  }
  std::optional<Scene> scene = load_server_scene(options, &error);
  if (!scene) return fail_setup(error);
  for (const std::string& w : scene->warnings) std::fprintf(stderr, "dhr-server: warning: scene: %s\n", w.c_str());
  std::unique_ptr<VisibilityTracer> tracer;
  try {
    tracer = create_tracer(options.backend, *scene, options.tracer);
  } catch (const std::exception& e) {
    return fail_run(std::string("cannot create the tracer: ") + e.what());
  }
  if (!scene->animation.empty() && tracer->moves())
    std::fprintf(stderr, "scene: %s play on the scene clock: each frame is traced at its pose's scene time\n",
                 describe_animations(*scene).c_str());
  else if (!scene->animation.empty())
    std::fprintf(stderr, "dhr-server: warning: scene: %s\n",
                 animations_not_played(*scene, tracer->backend()).c_str());

  ServeOptions serve;
  serve.bind_address = options.bind_address;
  serve.port = options.port;
  serve.max_seconds = options.max_seconds;
  serve.impairment = options.impairment;
  serve.metrics_port = options.metrics_port;
  ServiceConfig& config = serve.service;
  config.key = key;
  config.scene_id = std::filesystem::path(options.scene_path).stem().string();
  config.scene_hash = scene_content_hash(*scene);
  config.max_sessions = options.max_sessions;
  config.session_timeout_ns = int64_t{options.session_timeout_ms} * net::kNsPerMs;
  config.heartbeat_interval_ns = int64_t{options.heartbeat_ms} * net::kNsPerMs;
  config.skip_identical_pose = options.skip_identical_pose;
  config.token_seed = 0;  // std::random_device
  config.predict = options.predict;
  config.adaptive_fov.enabled = options.adaptive_fov;
  config.rate_control.enabled = options.rate_adapt;
  config.workers = options.workers;
  config.encode.threads = options.encode_threads;
  // Ranges follow the threads, 2 to 4: beyond 4 each range's partly filled shard and restarted models cost more
  // bytes than a thread saves time (docs/performance.md, "More ranges").
  config.encode.v2_ranges =
      options.encode_ranges != 0 ? options.encode_ranges : std::clamp(options.encode_threads, 2u, 4u);
  config.codec_v2 = options.codec_v2;
  config.soft_levels = options.soft_levels;
  const bool soft_scene = scene->has_soft_lights();
  const bool embree = tracer->backend() == TracerBackend::kEmbree;
  const LightSlots* slots = tracer->light_slots();
  config.reuse = options.reuse == ReuseChoice::kOn ||
                 (options.reuse == ReuseChoice::kAuto && shipped::reuse_by_default(embree, config.soft_levels, soft_scene));
  if (config.reuse && !embree)
    std::fprintf(stderr, "dhr-server: warning: --reuse on: the %s tracer does not reuse (Embree only); every pixel is "
                 "traced\n", tracer_backend_name(tracer->backend()));
  if (config.codec_v2)
    std::fprintf(stderr, "codec v2: each eye frame in %zu row ranges, coded on up to %zu threads\n",
                 config.encode.v2_ranges, config.encode.threads);
  std::fprintf(stderr, "reuse of earlier traces: %s\n",
               config.reuse                               ? "on"
               : options.reuse == ReuseChoice::kOff       ? "off (--reuse off)"
               : !embree                                  ? "off (not the Embree tracer)"
                                                          : "off (no soft levels here; --reuse on to force)");
  if (options.predict_horizon_ms >= 0.0)
    config.predict_horizon_ns = static_cast<int64_t>(options.predict_horizon_ms * static_cast<double>(net::kNsPerMs));

  std::fprintf(stderr, "%s\n", key ? "authentication on (key from --key-file)"
                                  : "authentication OFF (--insecure): anyone who reaches the port may connect");
  std::fprintf(stderr, "serving scene '%s' (%s, hash %016llx, %u lights) with %s (%s), %s%s%s%s\n",
               config.scene_id.c_str(), options.scene_path.c_str(), static_cast<unsigned long long>(config.scene_hash),
               tracer->light_count(), tracer_backend_name(tracer->backend()), tracer->device_description().c_str(),
               config.predict ? "tracing the views predicted for display" : "tracing the poses as sent (--no-predict)",
               config.adaptive_fov.enabled ? ", adaptive FOV" : "", options.impairment.active() ? ", impairment on send: " : "",
               options.impairment.active() ? options.impairment.describe().c_str() : "");
  if (slots) {  // more than 32 lights: the mask's fields are slots the lights share (docs/server.md, "Light slots")
    std::fprintf(stderr, "mask layout: light slots: %s; clients must offer them\n", slots->describe().c_str());
    for (const uint32_t i : slots->dropped())
      std::fprintf(stderr, "warning: light '%s' found no slot within the 32 mask bits: it is in no mask\n",
                   scene->lights[i].name.empty() ? ("light " + std::to_string(i)).c_str() : scene->lights[i].name.c_str());
  } else {
    std::fprintf(stderr, "mask layout: %s\n",
                 config.soft_levels ? layout_line(scene->lights).c_str() : "one bit per light (--soft-levels off)");
  }
  for (const std::string& name : config.soft_levels && !slots ? demoted_lights(scene->lights) : std::vector<std::string>{})
    std::fprintf(stderr, "warning: light '%s' has an extent but no room for its levels: one bit, traced to its centre\n",
                 name.c_str());
  try {
    return run_serve(serve, *tracer);
  } catch (const std::invalid_argument& e) {  // e.g. a --bind that is not an address
    return fail_setup(e.what());
  } catch (const std::exception& e) {
    return fail_run(e.what());
  }
}

}  // namespace dhr::server::cli
