// Rejects unusable views (non-finite values, zero quaternions, absurd positions, invalid FOVs) before they
// reach the network or the GPU: the frame reuses the last valid views instead, and each rejection is
// counted and logged (the first few, then every 100th, so a broken source cannot flood the log).
#pragma once
#include <array>
#include <cstdint>
#include <optional>

#include "math/pose.hpp"

namespace dhr::client {

class PoseGuard {
 public:
  // `fallback`: views used when the very first sample is already invalid.
  explicit PoseGuard(const std::array<View, 2>& fallback) : last_valid_(fallback) {}

  // Replaces `views` with the last valid views when any eye is unusable (returns true then: reused);
  // valid views are renormalized and remembered.
  bool filter(uint64_t frame, std::array<View, 2>& views);
  uint64_t rejected() const { return rejected_; }

  // Error text when a view cannot be rendered, std::nullopt when it can.
  static std::optional<std::string> check(const View& view);

 private:
  std::array<View, 2> last_valid_;
  uint64_t rejected_ = 0;
};

}  // namespace dhr::client
