#include "link/sequence_tracker.hpp"

#include <algorithm>

namespace dhr::client {

SequenceTracker::SequenceTracker(size_t window)
    : window_((std::max<size_t>(window, 64) + 63) / 64 * 64), bits_(window_ / 64, 0) {}

SequenceTracker::Result SequenceTracker::add(uint32_t sequence) {
  if (!started_) {
    // Extended numbers start at 2^32 so that going back up to 2^31 never underflows.
    first_ = highest_ = (uint64_t{1} << 32) | sequence;
    started_ = true;
    set(highest_);
    ++session_unique_;
    ++unique_;
    return Result::kNew;
  }
  const auto delta = static_cast<int32_t>(sequence - static_cast<uint32_t>(highest_));
  const uint64_t n = static_cast<uint64_t>(static_cast<int64_t>(highest_) + delta);
  if (n > highest_) {
    if (n - highest_ >= window_) {
      std::fill(bits_.begin(), bits_.end(), uint64_t{0});
    } else {
      for (uint64_t k = highest_ + 1; k < n; ++k) clear(k);
    }
    highest_ = n;
    set(n);
  } else {
    if (highest_ - n >= window_) {
      ++too_old_;
      return Result::kTooOld;
    }
    if (test(n)) {
      ++duplicates_;
      return Result::kDuplicate;
    }
    set(n);
    first_ = std::min(first_, n);
  }
  ++session_unique_;
  ++unique_;
  return Result::kNew;
}

uint64_t SequenceTracker::missing() const {
  if (!started_) return carried_missing_;
  const uint64_t span = highest_ - first_ + 1;
  return carried_missing_ + (span > session_unique_ ? span - session_unique_ : 0);
}

void SequenceTracker::restart() {
  carried_missing_ = missing();
  std::fill(bits_.begin(), bits_.end(), uint64_t{0});
  started_ = false;
  session_unique_ = 0;
}

}  // namespace dhr::client
