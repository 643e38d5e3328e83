#include "secure/replay_window.hpp"

namespace dhr::secure {

bool ReplayWindow::test(uint32_t s) const { return (seen_[(s % kWindow) / 64] >> (s % 64)) & 1u; }
void ReplayWindow::set(uint32_t s) { seen_[(s % kWindow) / 64] |= uint64_t{1} << (s % 64); }

bool ReplayWindow::accept(uint32_t sequence) {
  if (!any_) {
    any_ = true;
    highest_ = sequence;
    set(sequence);
    return true;
  }
  if (sequence > highest_) {
    const uint64_t advance = uint64_t{sequence} - highest_;
    if (advance >= kWindow) {
      seen_.fill(0);
    } else {
      for (uint64_t s = uint64_t{highest_} + 1; s <= sequence; ++s) {  // clear the slots the window slides over
        seen_[(s % kWindow) / 64] &= ~(uint64_t{1} << (s % 64));
      }
    }
    highest_ = sequence;
    set(sequence);
    return true;
  }
  if (highest_ - sequence >= kWindow) return false;  // too old to tell
  if (test(sequence)) return false;                   // seen
  set(sequence);
  return true;
}

}  // namespace dhr::secure
