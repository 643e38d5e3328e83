// The per-setting results (means over measured frames and eyes) and their JSON / CSV files.
#pragma once
#include "eval_session.hpp"
#include "eval_settings.hpp"

#include <optional>
#include <string>
#include <vector>

namespace dhr::eval {

struct SettingResult {
  Setting setting;
  uint64_t frames = 0;  // measured frames
  double bit_error = 0.0;
  std::vector<double> bit_error_per_light;
  // Mean |k shown - k exact| over the surface pixels of every measured eye-frame and the lights
  // (visibility_error.hpp); with hard lights only, the wrong bits' share of the surface pixels' bits, i.e.
  // bit_error / surface_frac.
  double visibility_error = 0.0;
  std::vector<double> visibility_error_per_light;
  double surface_frac = 0.0;  // surface pixels (the truth's primary rays hit) / display pixels
  double ssim = 0.0;
  double psnr = 0.0;  // from the mean MSE over frames and eyes; +inf when every frame matched exactly
  double mse = 0.0;
  std::optional<double> flip;  // mean FLIP (LDR) over frames and eyes; nullopt when not computed
  double unknown_frac = 0.0;
  double no_data_frac = 0.0;  // eye-frames with nothing received yet (local: all)
  // Shares of the display pixels (means over eye-frames): how pixels without a mask from their own eye's
  // buffer were filled, the depth test's disoccluded share, and known pixels whose undecided bits took the
  // shadow maps.
  double filled_other_eye_frac = 0.0;
  double filled_shadow_map_frac = 0.0;
  double filled_older_frac = 0.0;      // this eye's previous buffer
  double filled_neighbour_frac = 0.0;  // the nearest old pixel on the pixel's tangent plane
  double unfilled_frac = 0.0;  // shaded lit
  double disoccluded_frac = 0.0;
  double edges_shadow_map_frac = 0.0;
  double shadow_overrides_frac = 0.0;
  double motion_unknown_frac = 0.0;  // pixels with bits motion since the traced scene time made unknown
  double traced_depth_ms = 0.0;  // per eye-frame: GPU time of the traced camera's depth (0 when timestamps are off)
  double warp_ms = 0.0;          // per eye-frame: GPU time of the warp pass
  double client_ms = 0.0;     // per eye
  bool client_gpu_timed = false;
  std::string client_path;    // "forward", "deferred" or "mixed": the passes client_ms timed
  double server_ms = 0.0;     // per traced eye
  double server_rays_per_pixel = 0.0;  // occlusion rays per surface pixel the server traced (all lights)
  double soft_rays_per_pair = 0.0;     // of those, per surface pixel and soft light (TraceStats::soft_rays_per_pair)
  double encode_ms = 0.0;     // per traced eye
  double decode_ms = 0.0;     // per traced eye (all its shards)
  double bytes_per_frame = 0.0;  // visibility bytes on the wire per traced frame (both eyes)
  double response_ms = 0.0;
  double frames_behind = 0.0;     // mean p
  double frames_predicted = 0.0;  // mean x
  double prediction_fallback_frac = 0.0;
  double prediction_capped_frac = 0.0;
  double horizon_ms = 0.0;
  double fov_widened_frac = 0.0;  // traced eyes whose FOV the server widened beyond the guard band
  double fov_area_ratio = 0.0;    // mean traced / display tangent area of the traced eyes (1 when never widened)
  uint64_t poses_skipped_identical = 0;  // service: identical to the last traced pose, not traced again
  uint64_t poses_superseded = 0;         // service: replaced by a newer pose before it was traced
  uint64_t datagrams_lost = 0;
  double connect_ms = 0.0;  // virtual time of the connection phase (handshake + heartbeat round trip)
};

SettingResult summarize(const Setting& setting, const SettingTotals& totals, uint64_t frames);

// JSON: a list of objects (keys as in SettingResult; psnr null when infinite). CSV: one row per setting.
std::string results_json(const std::vector<SettingResult>& results);
std::string results_csv(const std::vector<SettingResult>& results);
// A fixed-width table for the terminal.
std::string results_table(const std::vector<SettingResult>& results);

}  // namespace dhr::eval
