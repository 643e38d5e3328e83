// How a light with an extent is sampled (trace/soft/soft_visibility.hpp), apart from the sampler so the tracer
// interface (TracerOptions::soft) can name it without Embree.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

namespace dhr::server {

struct SoftOptions {
  // Powers of two keep every stage a stratified (0,m,2)-net of the sequence.
  uint32_t initial_samples = 4;
  uint32_t max_samples = 32;
  uint32_t salt = 0;  // selects an independent scramble (soft_seed)
  // Uniform (non-adaptive) sampling with n samples: initial_samples = max_samples = n.
  static SoftOptions uniform(uint32_t n, uint32_t salt = 0) { return SoftOptions{n, n, salt}; }
};

inline constexpr uint32_t kMaxSoftSamples = 1u << 15;  // rays per pair fit 16 bits (SoftImage::rays)
// Error message when the options are unusable (0 samples, initial > max, more than kMaxSoftSamples).
std::optional<std::string> validate_soft_options(const SoftOptions& options);

}  // namespace dhr::server
