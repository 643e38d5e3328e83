// Replay protection for one direction of a session: accepts each 32-bit sequence number once, and none
// older than kWindow below the highest accepted (reordering within the window is fine). Check after the
// datagram's tag verified, so a forger cannot move the window.
#pragma once
#include <array>
#include <cstdint>

namespace dhr::secure {

class ReplayWindow {
 public:
  static constexpr uint32_t kWindow = 1024;
  // True (and remembered) the first time a sequence number within the window is seen.
  bool accept(uint32_t sequence);
  void reset() { *this = ReplayWindow{}; }

 private:
  bool test(uint32_t sequence) const;
  void set(uint32_t sequence);
  bool any_ = false;
  uint32_t highest_ = 0;
  std::array<uint64_t, kWindow / 64> seen_{};  // bit (s % kWindow) for s in (highest - kWindow, highest]
};

}  // namespace dhr::secure
