#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>
#include <utility>

#include "app/client_setup.hpp"
#include "render/light_layout.hpp"
#include "app/run_modes.hpp"
#include "traces/pose_trace.hpp"
#include "traces/eye_model.hpp"
#include "frame/frame_coordinator.hpp"
#include "log/log.hpp"
#include "frame/network_visibility_source.hpp"
#include "exit_signal.hpp"
#include "pose/orbit_pose_source.hpp"
#include "pose/pose_guard.hpp"
#include "pose/trace_pose_source.hpp"
#include "render/client_scene.hpp"
#include "scene/scene_hash.hpp"
#include "sink/png_sink.hpp"
#include "sink/stats_sink.hpp"
#include "vk/context.hpp"

namespace dhr::client {

namespace {

using SteadyClock = std::chrono::steady_clock;

std::unique_ptr<PoseSource> make_pose_source(const ClientOptions& options, const EyeModel& eyes) {
  std::string note;
  const TracePlacement placement = default_trace_placement(options.scene, &note);
  log::info("pose: %s", note.c_str());
  if (options.trace.empty()) return std::make_unique<OrbitPoseSource>(placement, eyes);
  PoseTrace trace;
  try {
    trace = TracePoseSource::load(options.trace);
  } catch (const std::exception& e) {  // unreadable or malformed: bad input (exit code 2), not a failed run
    throw InputError(e.what());
  }
  return std::make_unique<TracePoseSource>(std::move(trace), eyes, placement, options.trace);
}

}  // namespace

int run_offscreen(const ClientOptions& options) {
  const Scene scene = load_client_scene(options);
  const std::unique_ptr<NodeScriptPlayer> node_script = load_node_script_player(options, scene);
  const EyeModel eyes = EyeModel::monado_simulated();
  std::unique_ptr<PoseSource> poses = make_pose_source(options, eyes);
  log::info("pose source: %s", poses->describe().c_str());

  vk::ContextOptions vk_options;
  vk_options.app_name = "dhr-xrclient";
  vk_options.device = vk::parse_device_preference(options.vk_device);
  const std::unique_ptr<vk::Context> context = vk::Context::create(vk_options);
  const render::ClientScene client_scene(*context, scene);

  const Extent eye = options.eye_size;
  const GuardBand guard = options.guard.value_or(default_guard_band(eye));
  const std::unique_ptr<UdpVisibilityClient> link = connect_to_server(options, eye, guard, scene_content_hash(scene),
                                                                       client_scene);
  NetworkVisibilitySource source(link->client(), [&link] { return link->udp_counters().bytes_received; });
  source.set_node_script(node_script.get());

  FrameCoordinator coordinator(*context, client_scene, eye, source,
                               coordinator_options(options, context->info().is_discrete_gpu,
                                                   scene.has_soft_lights()));
  std::unique_ptr<StatsSink> stats;
  if (!options.stats_jsonl.empty()) stats = std::make_unique<StatsSink>(options.stats_jsonl);
  coordinator.set_on_frame([&stats](const FrameRecord& r) {
    if (stats) stats->write(r);
  });
  PngSink png(*context, options.offscreen, options.png_every);
  if (options.png_every != 0) describe_pictures(png, coordinator, options, scene.has_soft_lights());

  PoseGuard guard_poses = make_pose_guard(eyes);
  const uint64_t max_frames = options.frames.value_or(options.trace.empty() ? 300u : UINT32_MAX);
  RunSummary run;
  run.mode = "offscreen";
  run.eye = eye;
  run.guard = guard;
  run.pose_source = poses->describe();

  // Paced to the 90 Hz virtual clock of the pose source, so network delays in milliseconds mean the same
  // number of frames as on a headset; never waiting for the network.
  const SteadyClock::time_point start = SteadyClock::now();
  bool warned_failure = false;
  FramePose sample;
  while (run.frames < max_frames && poses->next(sample)) {
    if (exit_signal_received()) {
      run.exit = "signal";
      break;
    }
    if (std::chrono::duration<double>(SteadyClock::now() - start).count() > options.timeout_s) {
      log::error("offscreen: wall-clock cap of %.0f s reached after %llu frames", options.timeout_s,
                 static_cast<unsigned long long>(run.frames));
      run.exit = "timeout";
      break;
    }
    note_source_failure(source, warned_failure);
    if (scene_mismatch(*link)) {
      run.exit = kExitScene;
      break;
    }
    FrameInput input = frame_input(sample, guard_poses);
    if (node_script) input.node_overrides = &node_script->overrides();
    if (!coordinator.run_frame(input, png)) {
      log::error("offscreen: frame %llu failed: %s", static_cast<unsigned long long>(sample.frame),
                 coordinator.last_error().c_str());
      run.exit = "error";
      break;
    }
    ++run.frames;
    std::this_thread::sleep_until(start + std::chrono::nanoseconds(sample.display_time_ns + kVirtualFramePeriodNs));
  }
  if (!coordinator.finish() && run.exit == "clean") run.exit = "error";
  run.elapsed_s = std::chrono::duration<double>(SteadyClock::now() - start).count();
  run.fps = run.elapsed_s > 0.0 ? static_cast<double>(run.frames) / run.elapsed_s : 0.0;
  run.poses_rejected = guard_poses.rejected();
  run.png_files = png.files_written();
  if (run.frames == 0 && run.exit == "clean") run.exit = "no frames";
  return finish_run(run, options, coordinator.summary(), *link);
}

}  // namespace dhr::client
