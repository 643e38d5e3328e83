// dhr-eval's run options and the settings it sweeps (the cartesian product of the option lists).
#pragma once
#include "math/projection.hpp"
#include "render/shadow_maps.hpp"
#include "render/warp_reference.hpp"
#include "trace/soft/soft_options.hpp"
#include "truth_sampling.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dhr::eval {

// How the displayed frame gets its visibility:
//   kStale     the newest received buffer used as if it had been traced for the displayed pose (no warp)
//   kPaper     the paper's warp: the newest buffer reprojected from the pose it was traced for
//   kPaperPred kPaper, with the server tracing the pose its PosePredictor predicts for the display time
//   kLocal     no server: the client's own shadow maps shade every pixel (a standalone headset without DHR)
//   kFull      kPaperPred with every ingredient of the client's warp (render::WarpSettings::full()); single
//              ingredients can be switched off for an ablation ("full-no-depth", see Ingredient)
enum class Method { kStale, kPaper, kPaperPred, kLocal, kFull };
const char* method_name(Method method);

// The parts of `full` an ablation can switch off (bits of MethodSpec::without).
enum Ingredient : uint32_t {
  kIngredientBilinear = 1u,     // "bilinear": 2x2 samples and a vote
  kIngredientDepthTest = 2u,    // "depth": the disocclusion test
  kIngredientOtherEye = 4u,     // "other-eye": fill from the other eye
  kIngredientShadowFill = 8u,   // "shadow-fill": fill from the shadow maps
  kIngredientShadowEdges = 16u, // "shadow-edges": undecided bits from the shadow maps
  kIngredientPrediction = 32u,  // "pred": the server's pose prediction
  kIngredientShadowFirst = 64u, // "shadow-first": confident shadow-map bits first
  kIngredientAdaptiveFov = 128u, // "adaptive-fov": the server widens the traced FOV (server/session/include/session/fov_margin.hpp)
  kIngredientOlderBuffer = 256u, // "older": fill from this eye's previous buffer
  kIngredientNeighbour = 512u,   // "neighbour": fill from the nearest old pixel on the pixel's tangent plane
  kIngredientMotion = 1024u,     // "motion": bits motion since the traced scene time may change are unknown
  kIngredientSoftRefine = 2048u, // "soft-refine": soft fields shade with the used samples' band shares (soft_bands)
};

// A method and, for kFull, the ingredients switched off. `shipped`: the method "default", exactly what dhr-server
// and dhr-xrclient do without options (session/shipped_defaults.hpp, plan/shipped_defaults.hpp): `method` and
// `without` are what those defaults amount to (kPaperPred while the server predicts and the client warps the
// paper's way), and every decision below reads the shipped values themselves.
struct MethodSpec {
  Method method = Method::kPaper;
  uint32_t without = 0;  // Ingredient bits (kFull only)
  uint32_t depth_scale = 1;  // kFull with the depth test: the traced depth at 1/depth_scale resolution ("-depth-scale-N")
  // kFull: WarpSettings::edge_band ("-edge-band-N" where it is not the shipped band)
  uint32_t edge_band = client::shipped::kEdgeBand;
  // kFull with the depth test: the traced depth moved from the previous display frame ("-depth-splat";
  // WarpSettings::depth_splat), not rendered
  bool depth_splat = false;
  bool shipped = false;
  bool operator==(const MethodSpec&) const = default;
};
std::string method_name(const MethodSpec& spec);  // "full", "full-no-depth-no-pred", "default"
// "default", "stale", "paper", "paper+pred", "local", "full", "full-no-<ingredient>[-no-<ingredient>...]", each
// full form optionally followed by "-depth-scale-N" (N 2..16, not with -no-depth), then by "-depth-splat" (not with
// -no-depth), then by "-edge-band-N" (N 0..8, the shipped band when absent).
std::optional<MethodSpec> parse_method(const std::string& text);
// What ships (dhr-xrclient and dhr-server without options) in a scene with (`soft_scene`: Scene::has_soft_lights)
// or without soft lights: --warp auto's rule (client::resolve_warp). "default" parses to the form without; a run
// takes for_scene() of each method.
MethodSpec shipped_method(bool soft_scene);
MethodSpec for_scene(const MethodSpec& spec, bool soft_scene);
// The guard label of the default method's settings: the client's own guard band (shipped::guard_band).
inline constexpr const char* kShippedGuardLabel = "64x36";

struct Setting {
  MethodSpec method;
  double rtt_ms = 0.0;
  int x_max = -1;          // frames predicted at most (x = min(x_max, p)); -1: unlimited (x = p)
  std::string guard;       // as given: "0", "64x36" (pixels at 1920x1080, scaled to the eye size)
  GuardBand guard_band;    // per side, scaled to the eye size
};
// "paper+pred rtt=50ms x_max=all guard=64x36", for messages.
std::string setting_label(const Setting& setting);

struct RunOptions {
  std::string scene;
  uint32_t lights = 0;        // --lights: point lights added up to this many (bench/bench_lights.hpp); 0: the scene's
  double light_range = -1.0;  // --light-range, metres; < 0: default_bench_light_range
  std::string trace;
  std::string out_dir;
  std::vector<double> rtt_ms{0.0, 25.0, 50.0, 100.0, 200.0};
  std::vector<int> x_max{-1};
  std::vector<std::string> guard{"64x36"};
  std::vector<MethodSpec> methods{{Method::kStale}, {Method::kPaper}, {Method::kPaperPred}};
  uint64_t frames = 0;           // measured frames; 0: as many as the trace holds after the warm-up
  Extent eye{160, 120};
  double trace_start_s = 0.0;    // skip this much of the trace
  double jitter_ms = 0.0;        // per direction, uniform
  double loss = 0.0;             // per datagram, both directions
  double server_ms = 0.0;        // modelled server compute per traced frame (both eyes), virtual time
  uint64_t seed = 1;
  bool codec_v2 = true;          // --codec v2 (default) or v1
  double predict_window_ms = 0.0;       // paper+pred: velocity baseline (0: the two newest poses)
  double predict_max_horizon_ms = 100.0;  // paper+pred: the prediction horizon's cap (PosePredictorConfig's)
  double predict_soft_horizon_ms = 0.0;   // paper+pred: damping starts here (with predict_damping_ms > 0)
  double predict_damping_ms = 0.0;        // paper+pred: damping time constant beyond the soft horizon; 0: off
  double predict_quadratic_ms = 0.0;      // paper+pred: quadratic fit over this window (PosePredictorConfig's); 0: off
  render::ShadowMapSettings shadow_maps;  // local, full
  double plane_tolerance_rel = render::WarpSettings{}.plane_tolerance_rel;  // full's depth test
  double plane_tolerance_abs = render::WarpSettings{}.plane_tolerance_abs;
  std::optional<uint64_t> snapshot_frame;  // measured frame (0: the first) whose images go to <out>/snapshots
  std::optional<std::string> snapshot_crop;  // "X,Y,W,H": per round trip, one picture of that crop (snapshot_crops.hpp)
  uint32_t threads = 0;          // Embree threads (0: all cores)
  // The ground truth's samples per pixel and light with an extent (truth_sampling.hpp): first, and where they
  // disagree, all.
  // The server's sampling of lights with an extent (TracerOptions::soft): its default is what ships.
  server::SoftOptions server_soft;
  uint32_t truth_first_samples = kTruthFirstSamples;
  uint32_t truth_samples = kTruthSamples;
  // --render-path: deferred (every method and the truth on the deferred passes: the images differ only by
  // visibility) or shipped (each method on the path the client would take for it, the forward pass where it
  // applies, so client_ms is what ships; the truth on the forward pass, deferred-only methods then differ from it
  // by up to 2/255 per channel).
  bool shipped_path = false;
  bool progress = true;
};

// Splits "a,b,c" (no empty items). Each parser returns std::nullopt with a one-line reason in out_error.
std::vector<std::string> split_list(const std::string& text);
std::optional<std::vector<double>> parse_rtt_list(const std::string& text, std::string* out_error);
std::optional<std::vector<int>> parse_x_max_list(const std::string& text, std::string* out_error);  // ints, "all"
std::optional<std::vector<std::string>> parse_guard_list(const std::string& text, std::string* out_error);
std::optional<std::vector<MethodSpec>> parse_method_list(const std::string& text, std::string* out_error);
std::optional<Extent> parse_size(const std::string& text);  // "WxH", both >= 0
// A guard label ("0" or "WxH" at 1920x1080) scaled to the eye size.
GuardBand guard_for_eye(const std::string& label, Extent eye);

// What a setting's method means for the server and the client.
bool server_predicts(const MethodSpec& spec);        // paper+pred, full (unless without pred)
bool server_adapts_fov(const MethodSpec& spec);     // full (unless without adaptive-fov)
render::WarpSettings warp_settings(const MethodSpec& spec, const RunOptions& options);
bool uses_server_visibility(const MethodSpec& spec);  // all but local

// Every combination; kStale and kLocal ignore x_max (one setting per rtt and guard, x_max = -1).
std::vector<Setting> expand_settings(const RunOptions& options);

}  // namespace dhr::eval
