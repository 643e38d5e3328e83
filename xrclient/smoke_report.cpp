#include "smoke_report.hpp"

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

namespace dhr {

namespace {

glm::dvec3 position_of(const XrView& view) {
  return {view.pose.position.x, view.pose.position.y, view.pose.position.z};
}

nlohmann::json vec_json(const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

}  // namespace

void EyePoseStats::add(const std::array<XrView, 2>& views) {
  for (uint32_t eye = 0; eye < 2; ++eye) {
    const glm::dvec3 p = position_of(views[eye]);
    min_[eye] = samples_ == 0 ? p : glm::min(min_[eye], p);
    max_[eye] = samples_ == 0 ? p : glm::max(max_[eye], p);
  }
  distance_sum_ += glm::distance(position_of(views[0]), position_of(views[1]));
  ++samples_;
}

double EyePoseStats::mean_eye_distance() const {
  return samples_ == 0 ? 0.0 : distance_sum_ / static_cast<double>(samples_);
}

std::string smoke_report_json(const SmokeReport& report) {
  nlohmann::json j;
  j["runtime"] = report.runtime;
  j["system"] = report.system;
  j["world_space"] = report.world_space;
  j["vk_device"] = report.vk_device;
  j["eye_size"] = {{report.eye_size[0][0], report.eye_size[0][1]},
                   {report.eye_size[1][0], report.eye_size[1][1]}};
  j["swapchain_format"] = report.swapchain_format;
  j["frames"] = report.frames;
  j["frames_presented"] = report.frames_presented;
  j["fps"] = report.fps;
  j["reached_focused"] = report.reached_focused;
  j["states"] = report.states;
  nlohmann::json ranges = nlohmann::json::array();
  for (uint32_t eye = 0; eye < 2; ++eye) {
    // Without a single valid pose there is no range: null, never made-up zeros.
    if (report.poses.samples() == 0) {
      ranges.push_back(nullptr);
      continue;
    }
    ranges.push_back({{"min", vec_json(report.poses.min(eye))},
                      {"max", vec_json(report.poses.max(eye))}});
  }
  j["pose_range"] = ranges;
  j["pose_samples"] = report.poses.samples();
  j["ipd_m"] = report.poses.mean_eye_distance();
  j["exit"] = report.exit;
  j["signal"] = report.signal;
  // Non-finite numbers come out as null, which a checker rejects; runtime strings that are not
  // UTF-8 are repaired rather than thrown on.
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace dhr
