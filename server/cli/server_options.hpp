// dhr-server's command line: what to do (check, snapshot, serve clients over UDP) and with which
// settings. Parsing is separate from running so new modes only add a field and a branch.
#pragma once
#include "math/projection.hpp"
#include "session/shipped_defaults.hpp"
#include "net/impairment.hpp"
#include "trace/visibility_tracer.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dhr::server::cli {

enum class Mode { kNone, kCheck, kSnapshot, kServe, kGenKey };

// --reuse: auto turns it on where it was measured to save time (soft levels and a light with an extent).
enum class ReuseChoice { kAuto, kOn, kOff };

struct ServerOptions {
  Mode mode = Mode::kNone;
  std::string scene_path;    // resolved default when not given
  std::string snapshot_dir;
  TracerBackend backend = TracerBackend::kAuto;
  TracerOptions tracer;
  Extent eye_size{640, 480};
  std::optional<GuardBand> guard;       // explicit pixels; default: 64x36 at 1920x1080, scaled
  std::vector<std::string> cameras;     // "x,y,z:tx,ty,tz"; empty: the scene's bookmark file
  double fov_deg = 90.0;                // horizontal, of the displayed region
  std::string lights;                   // light specs (see parse_light_specs); empty: the scene's
  uint32_t repeat = 1;                  // traces per bookmark (the report gives the median time)
  // Serving (--port): the client chooses eye size, guard band and light count in its Hello.
  uint16_t port = 0;                    // 0: ephemeral
  std::string bind_address = "0.0.0.0";
  double max_seconds = 0.0;             // > 0: stop after this long
  uint32_t max_sessions = 8;
  uint32_t session_timeout_ms = 5000;
  uint32_t heartbeat_ms = 1000;
  bool skip_identical_pose = true;
  bool codec_v2 = true;                 // --codec v2 (default) or v1, for clients that offer v2
  bool soft_levels = true;              // --soft-levels on (default) or off, for clients that offer them
  ReuseChoice reuse = ReuseChoice::kAuto;  // --reuse auto|on|off (ServiceConfig::reuse; reuse_for_scene)
  bool predict = shipped::kPredict;     // server-side pose prediction (--no-predict: off, the paper's server)
  double predict_horizon_ms = -1.0;     // < 0: automatic (round trip + server time)
  bool adaptive_fov = shipped::kAdaptiveFov;            // widen the traced FOV from the measured shortfall (server/session/include/session/fov_margin.hpp)
  uint32_t workers = 2;                 // sessions traced in parallel (Embree; Vulkan: 1)
  uint32_t encode_threads = 2;          // threads coding one eye frame's v2 ranges (EncodeOptions::threads)
  uint32_t encode_ranges = 0;           // v2 row ranges per eye frame (EncodeOptions::v2_ranges); 0: the threads, 2..4
  uint16_t metrics_port = 0;            // > 0: Prometheus text on http://BIND:PORT/metrics
  bool rate_adapt = true;               // cap a session's trace rate when its client reports loss (--no-rate-adapt)
  net::ImpairmentParams impairment;     // on everything the server sends
  // Authentication (docs/security.md): serving needs --key-file unless --insecure; --gen-key writes a key.
  std::string key_file;
  bool insecure = false;
  std::string gen_key_path;
};

// The guard band in effect for the options (explicit, or the reference band scaled to the eye size).
GuardBand effective_guard_band(const ServerOptions& options);

// "4000" -> 4000. std::nullopt unless a decimal integer in [0, 65535].
std::optional<uint16_t> parse_port(const std::string& text);

// "640x480" -> Extent. std::nullopt unless both are integers in [min, kMaxBufferDimension].
std::optional<Extent> parse_extent(const std::string& text, uint32_t min_value);

// The default scene: <source dir>/assets/scenes/default_room.gltf, else relative to the executable
// (<exe dir>/../assets/... or <exe dir>/assets/...), else the repository-relative path itself.
std::string default_scene_path(const char* argv0);

// Parses argv. Returns the exit code to use right away (0 after --help, 2 after an error, with the
// message already printed) or std::nullopt to go on with out_options.
std::optional<int> parse_server_options(int argc, char** argv, ServerOptions& out_options);

}  // namespace dhr::server::cli
