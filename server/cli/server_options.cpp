#include "server_options.hpp"

#include "scene/scene.hpp"
#include "visibility/visibility.hpp"
#include "net/impairment_cli.hpp"

#include <CLI/CLI.hpp>
#include "cli/finite_range.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#ifndef DHR_SOURCE_DIR
#define DHR_SOURCE_DIR ""
#endif

namespace dhr::server::cli {
namespace {

bool parse_uint(const std::string& text, uint32_t& out) {
  if (text.empty() || text.size() > 9) return false;
  uint32_t v = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + static_cast<uint32_t>(c - '0');
  }
  out = v;
  return true;
}

}  // namespace

GuardBand effective_guard_band(const ServerOptions& options) {
  if (options.guard) return *options.guard;
  return paper_guard_band(options.eye_size);
}

std::optional<uint16_t> parse_port(const std::string& text) {
  uint32_t v = 0;
  if (!parse_uint(text, v) || v > 65535) return std::nullopt;
  return static_cast<uint16_t>(v);
}

std::optional<Extent> parse_extent(const std::string& text, uint32_t min_value) {
  const size_t x = text.find_first_of("xX");
  if (x == std::string::npos) return std::nullopt;
  Extent e;
  if (!parse_uint(text.substr(0, x), e.width) || !parse_uint(text.substr(x + 1), e.height)) return std::nullopt;
  if (e.width < min_value || e.height < min_value) return std::nullopt;
  if (e.width > kMaxBufferDimension || e.height > kMaxBufferDimension) return std::nullopt;
  return e;
}

std::string default_scene_path(const char* argv0) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path rel(kDefaultScenePath);
  const std::string source_dir = DHR_SOURCE_DIR;
  if (!source_dir.empty() && fs::exists(fs::path(source_dir) / rel, ec)) return (fs::path(source_dir) / rel).string();
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec && argv0) exe = fs::absolute(argv0, ec);
  if (!exe.empty()) {
    for (const fs::path& base : {exe.parent_path().parent_path(), exe.parent_path(),
                                 exe.parent_path().parent_path().parent_path()}) {
      if (fs::exists(base / rel, ec)) return (base / rel).string();
    }
  }
  return rel.string();
}

std::optional<int> parse_server_options(int argc, char** argv, ServerOptions& out) {
  CLI::App app{"dhr-server: ray-traced per-pixel, per-light shadow visibility for DHR-XR clients.\n"
               "Modes: --check (load and validate a scene), --snapshot DIR (trace camera bookmarks to PNGs),\n"
               "--port P (serve clients over UDP until SIGINT/SIGTERM or --max-seconds; the client's Hello\n"
               "chooses eye size, guard band and light count; a JSON line of statistics on exit).",
               "dhr-server"};
  std::string backend = "auto", eye_size = "640x480", guard, device = "auto", port;
  bool no_skip = false, check_flag = false;
  app.add_option("--scene", out.scene_path, "glTF 2.0 scene (.gltf/.glb); default: the project's default room")
      ->type_name("FILE");
  auto* check = app.add_flag("--check", check_flag, "load and validate the scene, print one JSON line, exit 0 (usable) or 2");
  auto* snapshot = app.add_option("--snapshot", out.snapshot_dir,
                                  "trace the left eye of every camera bookmark; write PNGs into DIR")
                     ->type_name("DIR");
  auto* serve = app.add_option("--port", port, "serve clients over UDP on this port (0: any free port, named on stderr)")
                  ->type_name("PORT");
  check->excludes(snapshot);
  check->excludes(serve);
  snapshot->excludes(serve);
  app.add_option("--backend", backend, "tracer backend: auto (Vulkan on a ray-tracing GPU, else Embree), embree, vulkan")
      ->capture_default_str();
  app.add_option("--eye-size", eye_size, "displayed size per eye, WxH")->capture_default_str()->type_name("WxH");
  app.add_option("--guard", guard, "guard band in pixels, WxH, both sides together, even (default: 64x36 at 1920x1080, scaled to the eye size)")
      ->type_name("WxH");
  app.add_option("--camera", out.cameras,
                 "camera x,y,z:tx,ty,tz (repeatable); default: <scene>.cameras.json beside the scene")
      ->type_name("CAMERA");
  app.add_option("--fov-deg", out.fov_deg, "horizontal field of view of the displayed region, degrees")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(1.0, 170.0));
  app.add_option("--lights", out.lights,
                 "replace the scene's lights, ';'-separated: point:x,y,z:r,g,b:I[:range] | "
                 "spot:x,y,z:dx,dy,dz:r,g,b:I:inner_deg,outer_deg[:range] | dir:dx,dy,dz:r,g,b:I")
      ->type_name("SPEC");
  app.add_option("--threads", out.tracer.threads, "CPU tracer threads (0 = all cores)")
      ->check(CLI::Range(0u, kMaxTracerThreads))
      ->capture_default_str();
  app.add_option("--repeat", out.repeat, "traces per bookmark; the report gives the median trace time")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(1u, 1000u));
  app.add_flag("--no-skip", no_skip, "trace every shadow ray (no N.L / range skipping, no light culling)");
  app.add_option("--vk-device", device, "Vulkan device: auto, gpu, lavapipe")->capture_default_str();
  app.add_flag("--vk-validation", out.tracer.vk_validation, "enable the Khronos validation layer (vulkan backend)");
  const char* kServeGroup = "Serving (--port)";
  app.add_option("--bind", out.bind_address, "address to bind: 0.0.0.0 (all IPv4), 127.0.0.1, :: (IPv6 and IPv4)")
      ->capture_default_str()
      ->type_name("ADDR")
      ->group(kServeGroup);
  app.add_option("--max-seconds", out.max_seconds, "stop by itself after this many seconds (0: run until a signal)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 1e7))
      ->type_name("S")
      ->group(kServeGroup);
  app.add_option("--max-sessions", out.max_sessions, "clients served at once; further Hellos get Bye(bad hello)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(1u, 1024u))
      ->group(kServeGroup);
  app.add_option("--session-timeout-ms", out.session_timeout_ms, "a session silent this long is closed (Bye timeout)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(100u, 3600000u))
      ->group(kServeGroup);
  app.add_option("--heartbeat-ms", out.heartbeat_ms, "heartbeat interval")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(10u, 60000u))
      ->group(kServeGroup);
  bool trace_identical = false;
  app.add_flag("--trace-identical-poses", trace_identical,
               "trace every pose, even one identical to the last traced (default: skip, refresh once a second)")
      ->group(kServeGroup);
  std::string codec = "v2";
  app.add_option("--codec", codec,
                 "visibility codec for clients that offer v2: v2 (context-modelled, against acknowledged frames) or v1 (LZ4)")
      ->capture_default_str()
      ->check(CLI::IsMember({"v1", "v2"}));
  std::string soft_levels = "on";
  app.add_option("--soft-levels", soft_levels,
                 "3-bit Gray-coded visibility levels for lights with an extent, for clients that offer them "
                 "(docs/protocol.md, \"Mask layout\"); off: one bit per light, traced to the light's centre")
      ->capture_default_str()
      ->check(CLI::IsMember({"on", "off"}))
      ->group(kServeGroup);
  std::string reuse = "auto";
  app.add_option("--reuse", reuse,
                 "take visibility from each eye's previous trace where it is certain (Embree; docs/server.md, "
                 "\"Reuse\"): auto = on when soft levels are on and the scene has a light with an extent (there it "
                 "halves the trace time; with hard shadows only it casts fewer rays but takes longer)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->group(kServeGroup);
  app.add_flag("--predict,!--no-predict", out.predict,
               "trace the views predicted for when the result is displayed (constant velocity from the "
               "client's last poses); on by default, --no-predict traces the poses as sent (the paper's server)")
      ->group(kServeGroup);
  app.add_option("--predict-horizon-ms", out.predict_horizon_ms,
                 "with --predict: fixed prediction horizon past the pose's display time (default: round trip "
                 "+ time on the server)")
      ->check(dhr::cli::FiniteRange(0.0, 1000.0))
      ->group(kServeGroup);
  app.add_flag("--adaptive-fov", out.adaptive_fov,
               "widen each eye's traced field of view beyond the guard band by how far the displayed views "
               "recently strayed from the traced ones (within the session's buffer: coarser pixels)")
      ->group(kServeGroup);
  app.add_option("--workers", out.workers,
                 "sessions traced in parallel, one per worker at a time (the Embree backend; Vulkan traces one at a "
                 "time)")
      ->check(CLI::Range(1u, 64u))
      ->capture_default_str()
      ->group(kServeGroup);
  app.add_option("--encode-threads", out.encode_threads,
                 "threads coding one eye frame with codec v2 (its row ranges; the bytes do not depend on it)")
      ->check(CLI::Range(1u, 64u))
      ->capture_default_str()
      ->group(kServeGroup);
  app.add_option("--encode-ranges", out.encode_ranges,
                 "row ranges each eye frame is cut into for codec v2, coded on their own, so that the threads can code "
                 "them at once (each costs a partly filled shard; default: --encode-threads within 2..4)")
      ->check(CLI::Range(1u, 64u))
      ->group(kServeGroup);
  app.add_option("--metrics-port", out.metrics_port,
                 "serve the statistics in the Prometheus text format on http://BIND:PORT/metrics (0: off)")
      ->check(CLI::Range(0, 65535))
      ->group(kServeGroup);
  bool no_rate_adapt = false;
  app.add_flag("--no-rate-adapt", no_rate_adapt,
               "trace every session as often as it sends poses, whatever its client reports losing (by default a "
               "session whose client reports more than 10 % loss is traced less often, docs/reliability.md)")
      ->group(kServeGroup);
  auto* gen_key = app.add_option("--gen-key", out.gen_key_path,
                                 "write a new random deployment key to FILE (mode 0600, never over an existing "
                                 "file) and exit; give the same file to the server and its clients (--key-file)")
                      ->type_name("FILE");
  app.add_option("--key-file", out.key_file,
                 "the deployment key (from --gen-key): clients must prove they hold it, every datagram is "
                 "authenticated and sealed (docs/security.md)")
      ->type_name("FILE")
      ->group(kServeGroup);
  app.add_flag("--insecure", out.insecure,
               "serve without a key: anyone who can reach the port may connect and read or forge datagrams")
      ->group(kServeGroup);
  net::add_impairment_options(app, out.impairment);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help (code 0) or the error
    return code == 0 ? 0 : 2;
  }
  auto fail = [](const std::string& message) {
    std::fprintf(stderr, "dhr-server: %s\n", message.c_str());
    return 2;
  };
  try {
    out.backend = parse_tracer_backend(backend);
  } catch (const std::exception& e) {
    return fail(std::string("--backend: ") + e.what());
  }
  if (device != "auto" && device != "gpu" && device != "lavapipe" && device != "cpu")
    return fail("--vk-device: expected auto, gpu or lavapipe, got '" + device + "'");
  out.tracer.vk_device = device;
  if (auto e = parse_extent(eye_size, 1)) {
    out.eye_size = *e;
  } else {
    return fail("--eye-size: expected WxH with 1 <= W,H <= " + std::to_string(kMaxBufferDimension) + ", got '" +
                eye_size + "'");
  }
  if (!guard.empty()) {
    auto g = parse_extent(guard, 0);
    const std::optional<GuardBand> band = g ? guard_band_from_total(g->width, g->height) : std::nullopt;
    if (!band) return fail("--guard: expected WxH, even pixel counts (both sides together), got '" + guard + "'");
    out.guard = *band;
    if (out.eye_size.width + g->width > kMaxBufferDimension || out.eye_size.height + g->height > kMaxBufferDimension)
      return fail("--guard: eye size plus guard band exceeds " + std::to_string(kMaxBufferDimension) + " pixels");
  }
  if (no_skip) out.tracer.skip = SkipOptions::none();
  out.rate_adapt = !no_rate_adapt;
  out.codec_v2 = codec == "v2";
  out.soft_levels = soft_levels == "on";
  out.reuse = reuse == "on" ? ReuseChoice::kOn : reuse == "off" ? ReuseChoice::kOff : ReuseChoice::kAuto;
  out.skip_identical_pose = !trace_identical;
  if (*serve) {
    const auto p = parse_port(port);
    if (!p) return fail("--port: expected an integer 0..65535, got '" + port + "'");
    out.port = *p;
    out.mode = Mode::kServe;
    if (out.bind_address.empty()) return fail("--bind: the address must not be empty");
  }
  if (out.mode == Mode::kServe) {
    if (out.key_file.empty() && !out.insecure)
      return fail("serving needs a key: --key-file FILE (make one with --gen-key FILE), or --insecure to serve "
                  "without authentication");
    if (!out.key_file.empty() && out.insecure) return fail("--key-file and --insecure exclude each other");
  }
  if (*gen_key) {
    if (out.gen_key_path.empty()) return fail("--gen-key: the file name must not be empty");
    out.mode = Mode::kGenKey;
  }
  if (check_flag) out.mode = Mode::kCheck;
  if (*snapshot) {
    out.mode = Mode::kSnapshot;
    if (out.snapshot_dir.empty()) return fail("--snapshot: the output directory must not be empty");
  }
  if (out.scene_path.empty()) out.scene_path = default_scene_path(argc > 0 ? argv[0] : nullptr);
  return std::nullopt;
}

}  // namespace dhr::server::cli
