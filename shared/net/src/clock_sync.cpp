#include "net/clock_sync.hpp"

namespace dhr::net {

std::optional<OffsetEstimate> offset_from_sample(const ClockSample& s) {
  int64_t round_trip = 0;  // t3 - t0
  int64_t hold = 0;        // t2 - t1
  int64_t up = 0;          // t1 - t0
  int64_t down = 0;        // t2 - t3
  if (__builtin_sub_overflow(s.t3_ns, s.t0_ns, &round_trip) ||
      __builtin_sub_overflow(s.t2_ns, s.t1_ns, &hold) ||
      __builtin_sub_overflow(s.t1_ns, s.t0_ns, &up) ||
      __builtin_sub_overflow(s.t2_ns, s.t3_ns, &down)) {
    return std::nullopt;
  }
  if (round_trip < 0 || hold < 0 || hold > round_trip) return std::nullopt;
  // (up + down) / 2 without overflowing the sum: halve first, then add the halves' remainders.
  const int64_t offset = up / 2 + down / 2 + (up % 2 + down % 2) / 2;
  return OffsetEstimate{offset, round_trip - hold};
}

ClockOffsetEstimator::ClockOffsetEstimator(size_t window) : window_(window == 0 ? 1 : window) {
  samples_.reserve(window_);
}

bool ClockOffsetEstimator::add_sample(const ClockSample& sample) {
  const std::optional<OffsetEstimate> estimate = offset_from_sample(sample);
  if (!estimate) {
    ++rejected_;
    return false;
  }
  ++accepted_;
  if (samples_.size() < window_) {
    samples_.push_back(*estimate);
    next_ = samples_.size() % window_;
  } else {
    samples_[next_] = *estimate;
    next_ = (next_ + 1) % window_;
  }
  // Smallest rtt wins; on ties the newest sample, so a drifting clock is tracked.
  best_.reset();
  const size_t count = samples_.size();
  for (size_t age = 0; age < count; ++age) {
    const size_t index = (next_ + count - 1 - age) % count;  // newest first
    if (!best_ || samples_[index].rtt_ns < best_->rtt_ns) best_ = samples_[index];
  }
  return true;
}

bool ClockOffsetEstimator::add_echo(int64_t echo_time_ns, int64_t echo_delay_ns,
                                    int64_t peer_send_time_ns, int64_t receive_time_ns) {
  int64_t t1 = 0;
  if (echo_delay_ns < 0 || __builtin_sub_overflow(peer_send_time_ns, echo_delay_ns, &t1)) {
    ++rejected_;
    return false;
  }
  return add_sample(ClockSample{echo_time_ns, t1, peer_send_time_ns, receive_time_ns});
}

void ClockOffsetEstimator::reset() {
  samples_.clear();
  next_ = 0;
  best_.reset();
  accepted_ = 0;
  rejected_ = 0;
}

}  // namespace dhr::net
