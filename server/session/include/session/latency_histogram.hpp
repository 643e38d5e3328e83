// A histogram of durations in milliseconds with fixed bucket bounds (Prometheus style: each bucket counts the
// values at or below its bound, the last one everything). Plain counters: the owner synchronizes.
#pragma once
#include <array>
#include <cstdint>

namespace dhr::server {

struct LatencyHistogram {
  static constexpr std::array<double, 10> kBoundsMs = {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000};
  std::array<uint64_t, kBoundsMs.size() + 1> counts{};  // per bucket (not cumulative); the last: above 1000
  double sum_ms = 0.0;
  uint64_t count = 0;

  void add(double ms) {
    size_t i = 0;
    while (i < kBoundsMs.size() && !(ms <= kBoundsMs[i])) ++i;
    ++counts[i];
    sum_ms += ms;
    ++count;
  }
};

}  // namespace dhr::server
