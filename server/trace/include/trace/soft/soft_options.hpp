// How a light with an extent is sampled (trace/soft/soft_visibility.hpp), apart from the sampler so the tracer
// interface (TracerOptions::soft) can name it without Embree.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

namespace dhr::server {

// Which scramble each pixel's samples use.
//   kPerLight: one scramble per light, the same sample points over the light for every pixel. A penumbra's
//     fraction is then a sum of the samples' hard shadows: its levels change along smooth contours, the same in
//     every frame (rect, disk and sun samples are fixed in the world), which the codec codes as it codes hard
//     edges: on living_room_area the levels cost 7.3x fewer bits than with kPerPixel (docs/soft-shadows.md). Its
//     error is bias shared by neighbours (banding below one level at 32 samples) instead of noise.
//   kPerPixel: an independent scramble per pixel (soft_seed of the pixel): unbiased noise, for references.
enum class SoftPattern : uint8_t { kPerLight, kPerPixel };

struct SoftOptions {
  // Powers of two keep every stage a stratified (0,m,2)-net of the sequence.
  uint32_t initial_samples = 8;
  uint32_t max_samples = 32;
  uint32_t salt = 0;  // selects an independent scramble (soft_seed)
  SoftPattern pattern = SoftPattern::kPerLight;
  // Uniform (non-adaptive) sampling with n samples: initial_samples = max_samples = n.
  static SoftOptions uniform(uint32_t n, uint32_t salt = 0, SoftPattern pattern = SoftPattern::kPerLight) {
    return SoftOptions{n, n, salt, pattern};
  }
  // The scramble seed of pixel (x, y)'s samples of light `light`, per `pattern` (light_sampler.cpp).
  uint32_t seed(uint32_t x, uint32_t y, uint32_t light) const;
};

inline constexpr uint32_t kMaxSoftSamples = 1u << 15;  // rays per pair fit 16 bits (SoftImage::rays)
// Error message when the options are unusable (0 samples, initial > max, more than kMaxSoftSamples).
std::optional<std::string> validate_soft_options(const SoftOptions& options);

}  // namespace dhr::server
