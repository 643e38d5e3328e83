// Small timing helpers the benchmarks share: wall milliseconds since a point, and the median of samples.
#pragma once
#include <algorithm>
#include <chrono>
#include <vector>

namespace dhr::bench {

inline double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// `if_empty` without samples (client_bench writes NaN as "not measured"; codec_bench 0).
inline double median(std::vector<double> v, double if_empty) {
  if (v.empty()) return if_empty;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace dhr::bench
