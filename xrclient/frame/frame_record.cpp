#include "frame/frame_record.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace dhr::client {

std::string frame_record_json(const FrameRecord& record) {
  nlohmann::ordered_json j;
  j["frame"] = record.frame;
  j["display_time_ns"] = record.display_time_ns;
  j["pose_reused"] = record.pose_reused;
  if (record.response_ms) j["response_ms"] = *record.response_ms;
  nlohmann::ordered_json eyes = nlohmann::ordered_json::array();
  for (const EyeFrameRecord& e : record.eyes) {
    nlohmann::ordered_json o;
    o["has_visibility"] = e.has_visibility;
    if (e.has_visibility) {
      o["visibility_frame"] = e.visibility_frame;
      o["age"] = e.age;
      o["complete"] = e.complete;
    }
    o["display_frame"] = e.display_frame;
    o["predicted_frames"] = e.predicted;
    o["gpu_valid"] = e.stats.gpu.valid;
    o["gbuffer_ms"] = e.stats.gpu.gbuffer_ms;
    o["warp_ms"] = e.stats.gpu.warp_ms;
    o["shading_ms"] = e.stats.gpu.shading_ms;
    o["forward"] = e.stats.forward;
    o["forward_ms"] = e.stats.gpu.forward_ms;
    o["total_ms"] = e.stats.gpu.total_ms;
    o["traced_depth_rendered"] = e.stats.traced_depth_rendered;  // the depth test's traced depth made this frame
    o["traced_depth_ms"] = e.stats.gpu.traced_depth_ms;
    if (e.stats.shadow_update.faces > 0) {  // eye 0 of a moving scene's frame: its shadow-map re-render
      o["shadow_update_lights"] = e.stats.shadow_update.lights;
      o["shadow_update_faces"] = e.stats.shadow_update.faces;
      o["shadow_update_ms"] = e.stats.gpu.shadow_update_ms;
    }
    o["known"] = e.stats.warp[render::WarpStatus::kKnown];
    o["filled_other_eye"] = e.stats.warp.filled_other_eye;
    o["filled_shadow_map"] = e.stats.warp.filled_shadow_map;
    o["filled_older"] = e.stats.warp.filled_older;
    o["filled_neighbour"] = e.stats.warp.filled_neighbour;
    o["surface"] = e.stats.warp.surface();
    o["unknown"] = e.stats.unknown_pixels();
    for (size_t s = 0; s < render::kWarpStatusCount; ++s) {
      o[render::to_string(static_cast<render::WarpStatus>(s))] = e.stats.warp.by_status[s];
    }
    eyes.push_back(std::move(o));
  }
  j["eyes"] = std::move(eyes);
  return j.dump();
}

void FrameSummary::add(const FrameRecord& record) {
  ++frames_;
  bool any_visibility = false;
  uint64_t shadow_pixels = 0;
  for (const EyeFrameRecord& e : record.eyes) {
    shadow_pixels += e.stats.warp.filled_shadow_map;
    pixels_other_eye_ += e.stats.warp.filled_other_eye;
    pixels_older_ += e.stats.warp.filled_older;
    pixels_neighbour_ += e.stats.warp.filled_neighbour;
    surface_ += e.stats.warp.surface();
    known_ += e.stats.warp[render::WarpStatus::kKnown];
    unknown_ += e.stats.unknown_pixels();
    if (e.has_visibility) {
      any_visibility = true;
      ages_.push_back(static_cast<double>(e.age));
    }
    if (e.stats.gpu.valid) {
      gbuffer_ms_.push_back(e.stats.gpu.gbuffer_ms);
      warp_ms_.push_back(e.stats.gpu.warp_ms);
      shading_ms_.push_back(e.stats.gpu.shading_ms);
      forward_ms_.push_back(e.stats.gpu.forward_ms);
      total_ms_.push_back(e.stats.gpu.total_ms);
      if (e.stats.shadow_update.faces > 0) shadow_update_ms_.push_back(e.stats.gpu.shadow_update_ms);
    }
  }
  if (any_visibility) ++frames_with_visibility_;
  if (!any_visibility && shadow_pixels > 0) ++frames_local_;
  pixels_shadow_map_ += shadow_pixels;
  if (record.response_ms) response_ms_.push_back(*record.response_ms);
}

double FrameSummary::predicted_frac() const {
  return surface_ == 0 ? 0.0 : static_cast<double>(known_) / static_cast<double>(surface_);
}

double FrameSummary::unknown_frac() const {
  return surface_ == 0 ? 0.0 : static_cast<double>(unknown_) / static_cast<double>(surface_);
}

std::optional<double> FrameSummary::median(std::vector<double> values) {
  if (values.empty()) return std::nullopt;
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1) return upper;
  const double lower = *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid));
  return 0.5 * (lower + upper);
}

}  // namespace dhr::client
