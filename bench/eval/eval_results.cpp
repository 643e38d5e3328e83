#include "eval_results.hpp"

#include "json_writer.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace dhr::eval {
namespace {

double mean(double sum, uint64_t count) { return count > 0 ? sum / static_cast<double>(count) : 0.0; }

std::string x_max_text(int x_max) { return x_max < 0 ? "all" : std::to_string(x_max); }

std::string number(double v, int decimals) {
  if (std::isinf(v)) return "inf";
  if (std::isnan(v)) return "nan";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

}  // namespace

SettingResult summarize(const Setting& setting, const SettingTotals& t, uint64_t frames) {
  SettingResult r;
  r.setting = setting;
  r.frames = frames;
  r.bit_error = mean(t.bit_error, t.eye_frames);
  for (const double v : t.bit_error_per_light) r.bit_error_per_light.push_back(mean(v, t.eye_frames));
  double visibility_sum = 0.0;
  for (const double v : t.visibility_error_per_light) {
    r.visibility_error_per_light.push_back(mean(v, t.surface_pixels));
    visibility_sum += v;
  }
  r.visibility_error = mean(visibility_sum, t.surface_pixels * t.visibility_error_per_light.size());
  r.surface_frac = mean(static_cast<double>(t.surface_pixels), t.display_pixels);
  r.ssim = mean(t.ssim, t.eye_frames);
  r.mse = mean(t.mse, t.eye_frames);
  if (t.flip_frames > 0) r.flip = mean(t.flip, t.flip_frames);
  r.psnr = r.mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / r.mse) : std::numeric_limits<double>::infinity();
  r.unknown_frac = mean(t.unknown_frac, t.eye_frames);
  r.no_data_frac = mean(static_cast<double>(t.eye_frames_without_data), t.eye_frames);
  r.filled_other_eye_frac = mean(t.filled_other_eye, t.eye_frames);
  r.filled_shadow_map_frac = mean(t.filled_shadow_map, t.eye_frames);
  r.filled_older_frac = mean(t.filled_older, t.eye_frames);
  r.filled_neighbour_frac = mean(t.filled_neighbour, t.eye_frames);
  r.unfilled_frac = mean(t.unfilled, t.eye_frames);
  r.disoccluded_frac = mean(t.disoccluded, t.eye_frames);
  r.edges_shadow_map_frac = mean(t.edges_shadow_map, t.eye_frames);
  r.shadow_overrides_frac = mean(t.shadow_overrides, t.eye_frames);
  r.motion_unknown_frac = mean(t.motion_unknown, t.eye_frames);
  r.traced_depth_ms = mean(t.traced_depth_ms, t.eye_frames);
  r.warp_ms = mean(t.warp_ms, t.eye_frames);
  r.client_ms = mean(t.client_ms, t.eye_frames);
  r.client_gpu_timed = t.eye_frames > 0 && t.client_gpu_timed == t.eye_frames;
  r.client_path = t.client_forward == t.eye_frames ? "forward" : t.client_forward == 0 ? "deferred" : "mixed";
  r.server_ms = mean(t.server_ms, t.traces);
  r.server_rays_per_pixel = mean(static_cast<double>(t.trace_stats.shadow_rays),
                                 t.trace_stats.pixels - t.trace_stats.background_pixels);
  r.soft_rays_per_pair = t.trace_stats.soft_rays_per_pair();
  r.encode_ms = mean(t.encode_ms, t.traces);
  r.decode_ms = mean(t.decode_ms, t.traces);
  r.bytes_per_frame = mean(static_cast<double>(t.bytes_down), t.traces) * 2.0;
  r.response_ms = mean(t.response_ms, t.responses);
  r.frames_behind = mean(t.frames_behind, t.eye_frames);
  r.frames_predicted = mean(t.frames_predicted, t.eye_frames);
  r.prediction_fallback_frac = mean(static_cast<double>(t.prediction_fallbacks), t.predictions);
  r.prediction_capped_frac = mean(static_cast<double>(t.prediction_capped), t.predictions);
  r.horizon_ms = mean(t.horizon_ms, t.predictions);
  r.fov_widened_frac = mean(static_cast<double>(t.eyes_fov_widened), t.traces);
  r.fov_area_ratio = t.eyes_fov_widened > 0 ? mean(t.fov_span_ratio, t.traces) : 1.0;
  r.poses_skipped_identical = t.poses_skipped_identical;
  r.poses_superseded = t.poses_superseded;
  r.datagrams_lost = t.datagrams_lost;
  r.connect_ms = t.connect_ms;
  return r;
}

std::string results_json(const std::vector<SettingResult>& results) {
  bench::JsonWriter w;
  w.begin_array();
  for (const SettingResult& r : results) {
    w.begin_object();
    w.value("method", method_name(r.setting.method));
    w.value("rtt_ms", r.setting.rtt_ms, 3);
    w.value("x_max", r.setting.x_max);
    w.value("guard", r.setting.guard);
    w.value("guard_px_x", 2 * r.setting.guard_band.x);  // both sides together
    w.value("guard_px_y", 2 * r.setting.guard_band.y);
    w.value("frames", static_cast<unsigned long long>(r.frames));
    w.value("bit_error", r.bit_error, 8);
    w.begin_array("bit_error_per_light");
    for (const double v : r.bit_error_per_light) w.value(nullptr, v, 8);
    w.end_array();
    w.value("visibility_error", r.visibility_error, 8);
    w.begin_array("visibility_error_per_light");
    for (const double v : r.visibility_error_per_light) w.value(nullptr, v, 8);
    w.end_array();
    w.value("surface_frac", r.surface_frac, 8);
    w.value("ssim", r.ssim, 8);
    w.value("psnr", r.psnr, 4);
    w.value("mse", r.mse, 6);
    w.value("flip", r.flip.value_or(std::numeric_limits<double>::quiet_NaN()), 8);  // null: not computed
    w.value("unknown_frac", r.unknown_frac, 8);
    w.value("no_data_frac", r.no_data_frac, 6);
    w.value("filled_other_eye_frac", r.filled_other_eye_frac, 8);
    w.value("filled_shadow_map_frac", r.filled_shadow_map_frac, 8);
    w.value("filled_older_frac", r.filled_older_frac, 8);
    w.value("filled_neighbour_frac", r.filled_neighbour_frac, 8);
    w.value("unfilled_frac", r.unfilled_frac, 8);
    w.value("disoccluded_frac", r.disoccluded_frac, 8);
    w.value("edges_shadow_map_frac", r.edges_shadow_map_frac, 8);
    w.value("shadow_overrides_frac", r.shadow_overrides_frac, 8);
    w.value("motion_unknown_frac", r.motion_unknown_frac, 8);
    w.value("traced_depth_ms", r.traced_depth_ms, 4);
    w.value("warp_ms", r.warp_ms, 4);
    w.value("client_ms", r.client_ms, 4);
    w.value("client_gpu_timed", r.client_gpu_timed);
    w.value("client_path", r.client_path);
    w.value("server_ms", r.server_ms, 4);
    w.value("server_rays_per_pixel", r.server_rays_per_pixel, 4);
    w.value("soft_rays_per_pair", r.soft_rays_per_pair, 4);
    w.value("encode_ms", r.encode_ms, 4);
    w.value("decode_ms", r.decode_ms, 4);
    w.value("bytes_per_frame", r.bytes_per_frame, 1);
    w.value("response_ms", r.response_ms, 3);
    w.value("frames_behind", r.frames_behind, 4);
    w.value("frames_predicted", r.frames_predicted, 4);
    w.value("prediction_fallback_frac", r.prediction_fallback_frac, 4);
    w.value("prediction_capped_frac", r.prediction_capped_frac, 4);
    w.value("horizon_ms", r.horizon_ms, 3);
    w.value("fov_widened_frac", r.fov_widened_frac, 4);
    w.value("fov_area_ratio", r.fov_area_ratio, 4);
    w.value("poses_skipped_identical", static_cast<unsigned long long>(r.poses_skipped_identical));
    w.value("poses_superseded", static_cast<unsigned long long>(r.poses_superseded));
    w.value("datagrams_lost", static_cast<unsigned long long>(r.datagrams_lost));
    w.value("connect_ms", r.connect_ms, 3);
    w.end_object();
  }
  w.end_array();
  return w.str() + "\n";
}

std::string results_csv(const std::vector<SettingResult>& results) {
  std::string out =
      "method,rtt_ms,x_max,guard,frames,bit_error,visibility_error,ssim,psnr,flip,unknown_frac,client_ms,server_ms,encode_ms,decode_ms,"
      "bytes_per_frame,response_ms,frames_behind,frames_predicted,prediction_fallback_frac,horizon_ms\n";
  for (const SettingResult& r : results) {
    out += std::string(method_name(r.setting.method)) + "," + number(r.setting.rtt_ms, 3) + "," +
           std::to_string(r.setting.x_max) + "," + r.setting.guard + "," + std::to_string(r.frames) + "," +
           number(r.bit_error, 8) + "," + number(r.visibility_error, 8) + "," + number(r.ssim, 8) + "," + number(r.psnr, 4) + "," +
           (r.flip ? number(*r.flip, 8) : std::string()) + "," + number(r.unknown_frac, 8) + "," + number(r.client_ms, 4) + "," + number(r.server_ms, 4) + "," +
           number(r.encode_ms, 4) + "," + number(r.decode_ms, 4) + "," + number(r.bytes_per_frame, 1) + "," +
           number(r.response_ms, 3) + "," + number(r.frames_behind, 4) + "," + number(r.frames_predicted, 4) + "," +
           number(r.prediction_fallback_frac, 4) + "," + number(r.horizon_ms, 3) + "\n";
  }
  return out;
}

std::string results_table(const std::vector<SettingResult>& results) {
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "%-11s %7s %5s %7s %9s %9s %7s %7s %7s %8s %9s %9s %9s %9s\n", "method",
                "rtt_ms", "x_max", "guard", "bit_err", "vis_err", "ssim", "psnr", "flip", "unknown", "client_ms", "server_ms", "bytes/fr",
                "resp_ms");
  out += line;
  for (const SettingResult& r : results) {
    std::snprintf(line, sizeof line, "%-11s %7.1f %5s %7s %9.5f %9.5f %7.4f %7s %7s %8.5f %9.3f %9.3f %9.0f %9.1f\n",
                  method_name(r.setting.method).c_str(), r.setting.rtt_ms, x_max_text(r.setting.x_max).c_str(),
                  r.setting.guard.c_str(), r.bit_error, r.visibility_error, r.ssim, number(r.psnr, 2).c_str(),
                  r.flip ? number(*r.flip, 4).c_str() : "-", r.unknown_frac,
                  r.client_ms, r.server_ms, r.bytes_per_frame, r.response_ms);
    out += line;
  }
  return out;
}

}  // namespace dhr::eval
