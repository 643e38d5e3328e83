// Setup shared by the offscreen and the OpenXR runs: the scene, the connection to dhr-server (waiting for
// the handshake, bounded), the pose guard's fallback, and the one-line JSON summary printed last.
#pragma once
#include <memory>
#include <string>

#include "app/client_options.hpp"
#include "traces/eye_model.hpp"
#include "frame/frame_coordinator.hpp"
#include "frame/frame_record.hpp"
#include "frame/visibility_source.hpp"
#include "scene/scene.hpp"
#include "link/node_script.hpp"
#include "link/udp_visibility_client.hpp"
#include "render/client_scene.hpp"
#include "pose/pose_guard.hpp"
#include "pose/pose_source.hpp"
#include "sink/png_sink.hpp"

namespace dhr::client {

// --scene with --lights applied, as dhr-server loads it (load_session_scene). Throws InputError("cannot load
// scene: <file>: <problem>").
Scene load_client_scene(const ClientOptions& options);

// Connects and waits for the Welcome (tick() every few ms, at most --connect-timeout); a Welcome that names
// another scene than `scene_hash` (scene_content_hash of the client's scene) is refused. Throws with one line:
// InputError (bad address, unusable key file), AuthenticationError, SceneMismatchError, or std::runtime_error
// ("no dhr-server reachable at HOST:PORT: ...", a refusal).
// `scene`: its light slots and soft fields (VisibilityClientConfig::light_slots and soft_lights).
std::unique_ptr<UdpVisibilityClient> connect_to_server(const ClientOptions& options, Extent eye, GuardBand guard,
                                                       uint64_t scene_hash, const render::ClientScene& scene);

// The client failed for good because the server (restarted, or answering late in offline mode) traces another
// scene: the run stops and exits with kExitSceneMismatch.
bool scene_mismatch(const UdpVisibilityClient& link);
inline constexpr const char* kExitScene = "scene mismatch";  // RunSummary::exit of such a run

// --node-script's player (nullptr without the option). Throws InputError("--node-script FILE:LINE: why") for a
// file that cannot be read or has a bad line: refused before the run.
std::unique_ptr<NodeScriptPlayer> load_node_script_player(const ClientOptions& options, const Scene& scene);

// The pose guard of a run; its fallback views are the eye model standing at the origin, looking down -Z.
PoseGuard make_pose_guard(const EyeModel& eyes);

// One frame's input: the sample's views through the pose guard (an unusable pose reuses the last good one).
FrameInput frame_input(const FramePose& sample, PoseGuard& guard);

// The frame loop's options from the command line: schedule, x_max, the shading view (a debug view also turns on
// the warp outputs it reads), the warp (--warp auto resolved for the scene: `scene_has_soft_lights`, any
// SceneLight::has_extent) and the render path on this device (`discrete_gpu`: vk::DeviceInfo::is_discrete_gpu).
CoordinatorOptions coordinator_options(const ClientOptions& options, bool discrete_gpu, bool scene_has_soft_lights);

// The --view as the summary names it: "shaded", "light:2", ...
std::string view_name(const ClientOptions& options);

// Writes views.jsonl next to the PNGs (`dhr-eval compare` renders the exact shading for those views).
void describe_pictures(PngSink& png, const FrameCoordinator& coordinator, const ClientOptions& options,
                       bool scene_has_soft_lights);

// Logs the visibility source's failure the first time it is seen (`warned` remembers it); rendering goes on.
void note_source_failure(const VisibilitySource& source, bool& warned);

struct RunSummary {
  std::string mode;  // "offscreen" | "openxr"
  std::string exit = "clean";
  uint64_t frames = 0;
  double fps = 0.0;
  double elapsed_s = 0.0;
  Extent eye;
  double render_scale = 1.0;  // OpenXR: eye / the runtime's eye size per axis (--render-scale)
  GuardBand guard;
  uint64_t poses_rejected = 0;
  uint64_t png_files = 0;
  std::string pose_source;
};

// The last stdout line: frames, fps, response_ms_median, bits_per_frame, predicted_frac, unknown_frac, ...
std::string summary_json(const RunSummary& run, const ClientOptions& options, const FrameSummary& frames,
                         const UdpVisibilityClient& link);

// The end of a run: says Bye (closes the link), prints the summary as the last stdout line, and returns
// the exit code (kExitOk for a clean run, kExitSceneMismatch for kExitScene, kExitNotClean otherwise).
int finish_run(const RunSummary& run, const ClientOptions& options, const FrameSummary& frames,
               UdpVisibilityClient& link);

}  // namespace dhr::client
