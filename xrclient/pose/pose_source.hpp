// Where each frame's two eye views come from: the OpenXR runtime, a recorded trace, or a script.
// Sources may produce anything (a runtime glitch, a hand-edited trace): PoseGuard (pose_guard.hpp) checks
// every sample before it reaches the network or the GPU.
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "math/pose.hpp"

namespace dhr::client {

class PoseSource {
 public:
  virtual ~PoseSource() = default;
  // The next frame's pose; false when the source has no more (a trace ended).
  virtual bool next(FramePose& out) = 0;
  virtual std::string describe() const = 0;
};

// Frame period of the virtual clock of trace and scripted sources: the 90 Hz headset rate.
inline constexpr int64_t kVirtualFramePeriodNs = 11'111'111;

}  // namespace dhr::client
