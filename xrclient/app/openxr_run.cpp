#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <memory>

#include "app/client_setup.hpp"
#include "render/light_layout.hpp"
#include "app/run_modes.hpp"
#include "app/start_pose.hpp"
#include "traces/eye_model.hpp"
#include "frame/frame_coordinator.hpp"
#include "log/log.hpp"
#include "frame/network_visibility_source.hpp"
#include "pose/openxr_pose_source.hpp"
#include "pose/pose_guard.hpp"
#include "render/client_scene.hpp"
#include "scene/scene_hash.hpp"
#include "session_loop.hpp"
#include "sink/png_sink.hpp"
#include "sink/stats_sink.hpp"
#include "sink/swapchain_sink.hpp"
#include "watchdog.hpp"
#include "xr/headset.hpp"
#include "xr/pose_convert.hpp"

namespace dhr::client {

namespace {

// Margin of the hard cap beyond the frame-phase cap: setup, exit walk and teardown.
constexpr std::chrono::seconds kHardCapMargin{30};

bool is_bgra(VkFormat f) { return f == VK_FORMAT_B8G8R8A8_SRGB || f == VK_FORMAT_B8G8R8A8_UNORM; }

}  // namespace

int run_openxr(const ClientOptions& options) {
  Watchdog watchdog(std::chrono::milliseconds(static_cast<int64_t>(options.timeout_s * 1000.0)) + kHardCapMargin,
                    "dhr-xrclient exceeded its wall-clock cap (a runtime call did not return)");
  const Scene scene = load_client_scene(options);
  const std::unique_ptr<NodeScriptPlayer> node_script = load_node_script_player(options, scene);

  xr::HeadsetOptions headset_options;
  headset_options.instance.app_name = "dhr-xrclient";
  headset_options.vulkan.app_name = "dhr-xrclient";
  headset_options.vulkan.device = vk::parse_device_preference(options.vk_device);
  headset_options.color_encoding =
      options.swapchain_format == "unorm" ? xr::ColorEncoding::kUnorm : xr::ColorEncoding::kSrgb;
  if (!options.start_at.empty()) {
    const Pose start = resolve_start_pose(options.start_at, options.scene);
    XrPosef pose{};
    pose.position = {static_cast<float>(start.position.x), static_cast<float>(start.position.y),
                     static_cast<float>(start.position.z)};
    pose.orientation = {static_cast<float>(start.orientation.x), static_cast<float>(start.orientation.y),
                        static_cast<float>(start.orientation.z), static_cast<float>(start.orientation.w)};
    headset_options.frame_loop.start_head = pose;
  }
  const std::unique_ptr<xr::Headset> headset = xr::Headset::open(headset_options);
  const vk::Context& vulkan = headset->vulkan();
  const xr::SwapchainDesc& desc = headset->swapchain(0).desc();
  if (headset->swapchain(1).desc().width != desc.width || headset->swapchain(1).desc().height != desc.height) {
    throw std::runtime_error("the runtime's eyes differ in size; this client renders both at one size");
  }
  // Render scale: the eyes are rendered (and traced) smaller, copied into the swapchain images' top-left
  // corners, and the projection layer's imageRect makes the compositor scale them to the view.
  const auto scaled = [&](uint32_t n) {
    return std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(static_cast<double>(n) * options.render_scale)));
  };
  const Extent eye{scaled(desc.width), scaled(desc.height)};
  headset->frame_loop().set_image_extent({eye.width, eye.height});
  const render::ClientScene client_scene(vulkan, scene);
  const GuardBand guard = options.guard.value_or(default_guard_band(eye));
  const std::unique_ptr<UdpVisibilityClient> link = connect_to_server(options, eye, guard, scene_content_hash(scene),
                                                                       client_scene);
  NetworkVisibilitySource source(link->client(), [&link] { return link->udp_counters().bytes_received; });
  source.set_node_script(node_script.get());

  CoordinatorOptions frame_options =
      coordinator_options(options, vulkan.info().is_discrete_gpu, scene.has_soft_lights());
  // The raw copy into a BGRA swapchain needs the channels swapped by the shading pass.
  frame_options.eye.shading.swap_red_blue = is_bgra(desc.format);
  FrameCoordinator coordinator(vulkan, client_scene, eye, source, frame_options);
  std::unique_ptr<StatsSink> stats;
  if (!options.stats_jsonl.empty()) stats = std::make_unique<StatsSink>(options.stats_jsonl);
  coordinator.set_on_frame([&stats](const FrameRecord& r) {
    if (stats) stats->write(r);
  });

  OpenXrPoseSource poses;
  if (!options.record_trace.empty()) poses.record_to(options.record_trace);
  SwapchainSink swapchain;
  SinkList sinks;
  sinks.add(swapchain);
  std::unique_ptr<PngSink> snapshots;
  if (!options.snapshot_dir.empty()) {
    snapshots = std::make_unique<PngSink>(vulkan, options.snapshot_dir, options.png_every,
                                          frame_options.eye.shading.swap_red_blue);
    if (options.png_every != 0) describe_pictures(*snapshots, coordinator, options, scene.has_soft_lights());
    sinks.add(*snapshots);
  }
  const EyeModel eyes = EyeModel::monado_simulated();
  PoseGuard guard_poses = make_pose_guard(eyes);
  RunSummary run;
  run.mode = "openxr";
  run.eye = eye;
  run.render_scale = options.render_scale;
  run.guard = guard;
  run.pose_source = poses.describe();
  bool warned_failure = false;

  const xr::RenderFn render = [&](const xr::FrameState& frame,
                                  const std::array<xr::EyeTarget, xr::kEyeCount>& t) -> xr::RenderedViews {
    poses.set_frame(frame);
    FramePose sample;
    poses.next(sample);
    note_source_failure(source, warned_failure);
    FrameInput input = frame_input(sample, guard_poses);
    if (node_script) input.node_overrides = &node_script->overrides();
    swapchain.set_targets(t);
    // A failure is reported after the frame (after_frame below) so the session can be walked down.
    if (!coordinator.run_frame(input, sinks)) return std::nullopt;
    ++run.frames;
    // The paper's schedule may have rendered an older frame's views: the compositor gets exactly those.
    std::array<XrView, xr::kEyeCount> rendered{};
    for (uint32_t e = 0; e < xr::kEyeCount; ++e) rendered[e] = xr::to_xr_view(coordinator.rendered_views()[e]);
    return rendered;
  };
  SessionLoopOptions loop_options;
  loop_options.frames = options.frames.value_or(300);
  loop_options.timeout_s = options.timeout_s;
  loop_options.log_name = "xrclient";
  const SessionLoopResult result = run_session_loop(*headset, loop_options, render, [&](const xr::FrameState&) {
    return coordinator.last_error().empty() && !scene_mismatch(*link);
  });
  if (!coordinator.finish() || !coordinator.last_error().empty()) {
    log::error("xrclient: rendering failed: %s", coordinator.last_error().c_str());
    run.exit = "error";
  } else if (scene_mismatch(*link)) {
    run.exit = kExitScene;
  } else {
    run.exit = result.exit;
  }
  std::string error;
  if (!poses.close_recording(&error)) log::error("record trace: %s", error.c_str());
  if (!options.record_trace.empty()) {
    log::info("recorded %zu poses into %s", poses.rows_recorded(), options.record_trace.c_str());
  }
  const xr::FrameLoop& loop = headset->frame_loop();
  run.elapsed_s = std::chrono::duration<double>(loop.last_end_time() - loop.first_end_time()).count();
  run.fps = loop.frames_ended() > 1 && run.elapsed_s > 0.0
                ? static_cast<double>(loop.frames_ended() - 1) / run.elapsed_s
                : 0.0;
  run.frames = loop.frames_presented();
  run.poses_rejected = guard_poses.rejected();
  if (snapshots) run.png_files = snapshots->files_written();
  return finish_run(run, options, coordinator.summary(), *link);
}

}  // namespace dhr::client
