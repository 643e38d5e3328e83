// Where each frame's two eye views come from: the OpenXR runtime, a recorded trace, or a script.
// Sources may produce anything (a runtime glitch, a hand-edited trace): PoseGuard (pose_guard.hpp) checks
// every sample before it reaches the network or the GPU.
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "core/pose.hpp"

namespace dhr::client {

struct PoseSample {
  uint64_t frame = 0;
  int64_t display_time_ns = 0;  // predicted display time (OpenXR XrTime, or virtual time from 0)
  std::array<View, 2> views{};  // 0 = left
};

class PoseSource {
 public:
  virtual ~PoseSource() = default;
  // The next frame's pose; false when the source has no more (a trace ended).
  virtual bool next(PoseSample& out) = 0;
  virtual std::string describe() const = 0;
};

// Frame period of the virtual clock of trace and scripted sources: the 90 Hz headset rate.
inline constexpr int64_t kVirtualFramePeriodNs = 11'111'111;

}  // namespace dhr::client
