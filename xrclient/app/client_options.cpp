#include "app/client_options.hpp"

#include <CLI/CLI.hpp>
#include "cli/finite_range.hpp"
#include <cstdio>
#include <string_view>

#include "net/impairment_cli.hpp"
#include "vk/context.hpp"

namespace dhr::client {

std::optional<Extent> parse_extent(const std::string& text, std::string* out_error) {
  unsigned w = 0;
  unsigned h = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%ux%u%c", &w, &h, &tail) != 2) {
    if (out_error) *out_error = "expected WxH (e.g. 320x240), got '" + text + "'";
    return std::nullopt;
  }
  return Extent{w, h};
}

GuardBand default_guard_band(Extent eye) { return shipped::guard_band(eye); }

namespace {

CLI::Validator extent_validator(uint32_t min_value, bool even) {
  return CLI::Validator(
      [min_value, even](std::string& text) -> std::string {
        std::string error;
        const auto e = parse_extent(text, &error);
        if (!e) return error;
        if (e->width < min_value || e->height < min_value || e->width > kMaxImageDimension ||
            e->height > kMaxImageDimension) {
          return "sizes must be within " + std::to_string(min_value) + ".." + std::to_string(kMaxImageDimension);
        }
        if (even && (e->width % 2 != 0 || e->height % 2 != 0)) return "guard band sizes must be even (split per side)";
        return std::string();
      },
      "WxH");
}

// "shaded", "unknown", "motion", "albedo", "normal" or "light:N" (N in 0..31) into out.view / out.view_light.
bool parse_view(const std::string& text, ClientOptions& out) {
  for (const char* name : {"shaded", "unknown", "motion", "albedo", "normal"}) {
    if (text == name) {
      out.view = text;
      return true;
    }
  }
  constexpr std::string_view kLight = "light:";
  if (text.size() <= kLight.size() || text.size() > kLight.size() + 2 || text.compare(0, kLight.size(), kLight) != 0) {
    return false;
  }
  uint32_t n = 0;
  for (size_t i = kLight.size(); i < text.size(); ++i) {
    if (text[i] < '0' || text[i] > '9') return false;
    n = n * 10 + static_cast<uint32_t>(text[i] - '0');
  }
  if (n > 31) return false;
  out.view = "light";
  out.view_light = n;
  return true;
}

}  // namespace

ParseOutcome parse_client_options(int argc, char** argv, ClientOptions& out, int* exit_code) {
  CLI::App app{"DHR-XR headset client: renders a scene with ray-traced shadows streamed from dhr-server"};
  std::string eye_size;
  std::string guard;
  std::string schedule = schedule_name(out.schedule);
  std::string view = "shaded";
  uint32_t frames = 0;
  app.add_flag("--smoke", out.smoke, "Smoke session: clear both eyes for --frames frames, print one JSON line");
  app.add_option("--scene", out.scene, "glTF scene (.gltf/.glb), the same the server traces");
  app.add_option("--lights", out.lights,
                 "replace the scene's lights, as dhr-server --lights (the same specs: the server's Welcome names "
                 "the scene hash, lights included, and a mismatch ends the run with exit code 5)");
  app.add_option("--server", out.server, "dhr-server address HOST:PORT");
  app.add_option("--key-file", out.key_file,
                 "the deployment key the server was given (dhr-server --gen-key FILE): authenticates and seals "
                 "every datagram (docs/security.md); without it the client speaks only to an --insecure server")
      ->type_name("FILE");
  app.add_option("--trace", out.trace, "Play this pose trace offscreen (needs --offscreen)");
  app.add_option("--offscreen", out.offscreen, "Render offscreen (no OpenXR): PNGs and statistics go to DIR");
  app.add_option("--frames", frames, "Frames to present (default 300; with --trace: the trace's length)")
      ->check(CLI::PositiveNumber);
  app.add_option("--timeout", out.timeout_s, "Wall-clock cap of the frame phase, seconds")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.1, 86400.0));
  app.add_option("--eye-size", eye_size, "Offscreen per-eye size WxH (default 320x240, Monado's)")
      ->check(extent_validator(1, false));
  app.add_option("--guard", guard, "Guard band WxH: extra traced pixels per axis (even; default: 64x36 scaled "
                                   "from 1920x1080 to the eye size)")
      ->check(extent_validator(0, true));
  app.add_option("--png-every", out.png_every, "Offscreen: write both eyes as PNG every Nth frame (0: never)")
      ->capture_default_str();
  app.add_option("--snapshot-dir", out.snapshot_dir,
                 "OpenXR: also write the presented eyes as PNG every --png-every frames");
  app.add_option("--stats-jsonl", out.stats_jsonl, "Per-frame statistics as JSON lines into FILE");
  app.add_option("--node-script", out.node_script,
                 "Move nodes at run time: JSON lines {\"t\": s, \"node\": name or index, \"translation\": [x,y,z], "
                 "\"rotation\": [x,y,z,w], \"scale\": [x,y,z]}, each sent when the scene clock reaches t "
                 "(docs/motion.md)");
  app.add_option("--schedule", schedule,
                 "paper: show frame n-p+x; newest: always the newest pose; stale: no warp (reference)")
      ->capture_default_str()
      ->check(CLI::IsMember({"paper", "newest", "stale"}));
  std::string warp = to_string(out.warp);
  app.add_option("--warp", warp,
                 "paper: the paper's warp (unknown pixels lit); full: 2x2 depth-tested lookups, the other eye's "
                 "buffer and the client's shadow maps (docs/client.md, Warp rule); edges: 2x2 lookups, bits they "
                 "agree on from the server, the others and unknown pixels from the client's shadow maps (forward); "
                 "edges-depth: edges plus the depth test against the traced camera's depth rendered at 1/--depth-scale "
                 "resolution for every arriving buffer (samples off the pixel's tangent plane, disocclusions, not used); "
                 "auto: edges-depth in a scene with a light that has an extent (area, sphere, sun), else edges")
      ->capture_default_str()
      ->check(CLI::IsMember({"paper", "full", "edges", "edges-depth", "auto"}));
  app.add_option("--depth-scale", out.depth_scale,
                 "edges-depth, full: render the traced camera's depth for the depth test at 1/N of the traced resolution "
                 "per axis (1: full resolution)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 16u));
  std::string traced_depth = to_string(out.traced_depth);
  app.add_option("--traced-depth", traced_depth,
                 "edges-depth, full: where the depth test's traced depth comes from: raster (the traced camera "
                 "rendered, a second raster pass) or splat (this eye's previous frame's depth moved into the traced "
                 "camera, one compute pass; docs/client.md)")
      ->capture_default_str()
      ->check(CLI::IsMember({"raster", "splat"}));
  app.add_option("--edge-band", out.edge_band,
                 "edges, edges-depth, full: a light's shadow edge within N traced pixels of a lookup's samples makes "
                 "its bit the shadow maps' (hard lights; 0: only where the 2x2 samples disagree)")
      ->capture_default_str()
      ->check(CLI::Range(0u, 8u));
  app.add_option("--shadow-fill-period-ms", out.shadow_fill_period_ms,
                 "moving scenes: while the client's shadow maps only fill (both eyes show visibility traced for the "
                 "scene time shown), each light's map is re-rendered once per this much scene time, in turns "
                 "(0: every frame)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.0, 10000.0));
  app.add_option("--start-at", out.start_at,
                 "OpenXR: start the head here (the world space offset by poseInReferenceSpace, heading only): "
                 "bookmark (the scene's first camera bookmark), bookmark:N (its N-th or the one named N) or "
                 "x,y,z:tx,ty,tz");
  app.add_option("--render-scale", out.render_scale,
                 "OpenXR: render (and have the server trace) each eye at this fraction of the runtime's eye size per "
                 "axis; the compositor scales the image up (the projection layer's imageRect)")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.1, 1.0));
  std::string render_path = to_string(out.render_path);
  app.add_option("--render-path", render_path,
                 "forward: one forward pass that warps and shades where it applies (the paper's warp or edges, the "
                 "shaded view, at most 8 lights), else the deferred passes; deferred: always G-buffer, warp, shading; "
                 "auto: forward except on a discrete GPU (docs/client.md)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "forward", "deferred"}));
  std::string codec = "v2";
  app.add_option("--codec", codec, "visibility codec to offer: v2 (the server may still choose v1) or v1")
      ->capture_default_str()
      ->check(CLI::IsMember({"v1", "v2"}));
  app.add_option("--x-max", out.x_max, "Paper schedule: frames predicted at most")->capture_default_str();
  app.add_option("--record-trace", out.record_trace, "OpenXR: record the session's views as a canonical trace");
  app.add_option("--connect-timeout", out.connect_timeout_s, "Give up on the server after this many seconds")
      ->capture_default_str()
      ->check(dhr::cli::FiniteRange(0.1, 600.0));
  app.add_option("--vk-device", out.vk_device, "Vulkan device: auto | gpu | lavapipe")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "gpu", "lavapipe", "cpu"}));
  app.add_option("--swapchain-format", out.swapchain_format, "Preferred swapchain colour encoding: srgb | unorm")
      ->capture_default_str()
      ->check(CLI::IsMember({"srgb", "unorm"}));
  app.add_option("--view", view,
                 "What the eyes show: shaded | light:N (light N's predicted visibility: white lit, black shadowed, "
                 "red unknown) | unknown (shaded, unknown pixels magenta) | motion (warp motion vectors) | "
                 "albedo | normal")
      ->capture_default_str();
  net::add_impairment_options(app, out.impairment);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help (code 0) or the error
    *exit_code = code == 0 ? 0 : 2;  // every usage error exits 2, as dhr-server's
    return ParseOutcome::kExit;
  }
  auto usage = [&](const std::string& message) {
    std::fprintf(stderr, "error: %s (see --help)\n", message.c_str());
    *exit_code = 2;
    return ParseOutcome::kExit;
  };
  if (frames > 0) out.frames = frames;
  if (!eye_size.empty()) out.eye_size = *parse_extent(eye_size, nullptr);
  if (!guard.empty()) {
    const Extent g = *parse_extent(guard, nullptr);
    out.guard = *guard_band_from_total(g.width, g.height);  // even: checked by the validator above
  }
  out.schedule = *parse_schedule(schedule);
  out.codec_v2 = codec == "v2";
  out.warp = warp == "full"             ? WarpChoice::kFull
             : warp == "edges"          ? WarpChoice::kEdges
             : warp == "edges-depth"    ? WarpChoice::kEdgesDepth
             : warp == "auto"           ? WarpChoice::kAuto
                                        : WarpChoice::kPaper;
  out.render_path = parse_render_path(render_path).value_or(shipped::kRenderPath);
  out.traced_depth = traced_depth == "splat" ? TracedDepth::kSplat : TracedDepth::kRaster;
  if (!parse_view(view, out)) {
    return usage("--view '" + view + "': expected shaded, light:N (N 0..31), unknown, motion, albedo or normal");
  }
  if (out.smoke) {
    out.smoke_options.frames = out.frames.value_or(out.smoke_options.frames);
    out.smoke_options.timeout_s = app.count("--timeout") > 0 ? out.timeout_s : out.smoke_options.timeout_s;
    out.smoke_options.device = vk::parse_device_preference(out.vk_device);
    out.smoke_options.color_encoding =
        out.swapchain_format == "unorm" ? xr::ColorEncoding::kUnorm : xr::ColorEncoding::kSrgb;
    return ParseOutcome::kRun;
  }
  if (out.scene.empty()) return usage("--scene FILE is required (or --smoke)");
  if (out.server.empty()) return usage("--server HOST:PORT is required");
  if (!out.trace.empty() && out.offscreen.empty()) return usage("--trace plays offscreen: add --offscreen DIR");
  if (!out.start_at.empty() && !out.offscreen.empty()) {
    return usage("--start-at places the OpenXR head: offscreen, the poses come from --trace or the orbit");
  }
  if (!out.record_trace.empty() && !out.offscreen.empty()) {
    return usage("--record-trace records OpenXR views: it cannot be combined with --offscreen");
  }
  return ParseOutcome::kRun;
}

}  // namespace dhr::client
