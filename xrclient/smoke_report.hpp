// What a smoke run measured, and its one-line JSON form (the last line dhr-xrclient --smoke
// prints on stdout).
#pragma once
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "xr/openxr_vulkan.hpp"

namespace dhr {

// Per eye min/max of the eye positions, and the mean distance between the two eyes.
class EyePoseStats {
 public:
  void add(const std::array<XrView, 2>& views);
  uint64_t samples() const { return samples_; }
  const glm::dvec3& min(uint32_t eye) const { return min_[eye]; }
  const glm::dvec3& max(uint32_t eye) const { return max_[eye]; }
  double mean_eye_distance() const;  // 0 without samples

 private:
  uint64_t samples_ = 0;
  std::array<glm::dvec3, 2> min_{};
  std::array<glm::dvec3, 2> max_{};
  double distance_sum_ = 0.0;
};

struct SmokeReport {
  std::string runtime;  // name + version
  std::string system;
  std::string world_space;  // STAGE or LOCAL
  std::string vk_device;
  std::array<std::array<uint32_t, 2>, 2> eye_size{};
  int64_t swapchain_format = 0;  // VkFormat
  uint64_t frames = 0;            // frames ended (xrEndFrame succeeded)
  uint64_t frames_presented = 0;  // ... with a projection layer
  double fps = 0.0;               // (frames - 1) / time between first and last xrEndFrame
  bool reached_focused = false;
  std::vector<std::string> states;
  EyePoseStats poses;
  std::string exit = "error";  // clean | timeout | loss_pending | instance_lost | error
  int signal = 0;              // SIGINT/SIGTERM that asked for the exit, 0 if none
};

std::string smoke_report_json(const SmokeReport& report);

}  // namespace dhr
