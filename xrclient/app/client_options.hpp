// dhr-xrclient's command line (docs/client.md, "Command line"). Parsing is separate from running so the
// executable's main stays small and the contract is in one place.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "math/projection.hpp"
#include "plan/schedule.hpp"
#include "plan/shipped_defaults.hpp"
#include "net/impairment.hpp"
#include "smoke.hpp"

namespace dhr::client {

struct ClientOptions {
  bool smoke = false;
  SmokeOptions smoke_options;  // --frames, --timeout, --vk-device, --swapchain-format also apply to --smoke

  std::string scene;        // --scene FILE
  std::string lights;       // --lights SPECS: the override the server was started with (scene hash must match)
  std::string server;       // --server HOST:PORT
  std::string trace;        // --trace FILE (offscreen playback)
  std::string offscreen;    // --offscreen DIR (no OpenXR; PNGs and statistics)
  std::optional<uint32_t> frames;  // --frames N (default: 300, or the trace's length)
  double timeout_s = 120.0;        // wall-clock cap of the frame phase
  Extent eye_size{320, 240};       // --eye-size WxH (offscreen; OpenXR uses the runtime's size)
  std::optional<GuardBand> guard;  // per side, from --guard WxH (both sides together, even)
  uint32_t png_every = 30;         // --png-every N (offscreen, --snapshot-dir; 0 = none)
  std::string snapshot_dir;        // --snapshot-dir DIR (OpenXR: PNGs of the presented images)
  std::string stats_jsonl;         // --stats-jsonl FILE
  Schedule schedule = shipped::kSchedule;
  uint32_t x_max = shipped::kXMax;
  bool codec_v2 = true;  // --codec v2 (offer v2; the server decides) or v1 (LZ4 only)
  RenderPath render_path = shipped::kRenderPath;  // --render-path (forward_pass_for, render::EyePipelineOptions::forward)
  WarpChoice warp = shipped::kWarp;  // --warp
  uint32_t depth_scale = shipped::kDepthScale;  // --depth-scale
  uint32_t edge_band = shipped::kEdgeBand;      // --edge-band
  double shadow_fill_period_ms = static_cast<double>(shipped::kShadowFillPeriodNs) * 1e-6;  // --shadow-fill-period-ms
  TracedDepth traced_depth = shipped::kTracedDepth;  // --traced-depth
  std::string record_trace;  // --record-trace FILE (OpenXR path)
  std::string node_script;   // --node-script FILE: app-moved nodes (link/node_script.hpp)
  double connect_timeout_s = 5.0;
  std::string vk_device = "auto";
  std::string swapchain_format = "srgb";
  std::string start_at;        // --start-at SPEC (OpenXR: where the head starts; app/start_pose.hpp)
  double render_scale = 1.0;  // OpenXR: eyes rendered (and traced) at this fraction of the swapchain size per axis
  std::string view = "shaded";  // --view: shaded | light | unknown | motion | albedo | normal
  uint32_t view_light = 0;      // --view light:N
  net::ImpairmentParams impairment;
  std::string key_file;  // the deployment key (docs/security.md); empty: no authentication
};

enum class ParseOutcome { kRun, kExit };

// Parses argv. kExit with *exit_code set for --help (0) and for usage errors (2, message printed).
ParseOutcome parse_client_options(int argc, char** argv, ClientOptions& out, int* exit_code);

// "WxH" with both in 1..kMaxImageDimension (guard: 0..4096, even).
std::optional<Extent> parse_extent(const std::string& text, std::string* out_error);

// The guard band used when --guard is not given: the paper's 64x36 at 1920x1080 scaled to the eye size.
GuardBand default_guard_band(Extent eye);

}  // namespace dhr::client
