// Small timing helpers the benchmarks share: wall milliseconds since a point, and the median, mean and largest of
// samples.
#pragma once
#include <algorithm>
#include <chrono>
#include <numeric>
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

inline double mean(const std::vector<double>& v, double if_empty) {
  return v.empty() ? if_empty : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

inline double largest(const std::vector<double>& v, double if_empty) {
  return v.empty() ? if_empty : *std::max_element(v.begin(), v.end());
}

}  // namespace dhr::bench
