// Fractional visibility quantized to a few levels per light, and the Gray code the levels are stored in.
//
// Levels are evenly spaced over [0, 1] with both ends exact (level 0 = fully hidden, levels - 1 = fully
// visible), so hard-shadow pixels and punctual lights survive quantization unchanged. docs/server.md
// ("Soft visibility") has the measurement behind kDefaultSoftLevels: the quantization error against the
// sampling noise at the default sample counts. Server (the soft tracer) and client (the warp, the shading,
// PCSS) share it through visibility_layout.hpp.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace dhr {

inline constexpr uint32_t kMinSoftLevels = 2;    // 1 bit: the hard bit
inline constexpr uint32_t kMaxSoftLevels = 256;  // levels are stored in 8 bits
// 8 levels = 3 bits per light (docs/server.md, "Soft visibility": at 32 samples quantizing to 8 levels adds
// far less error than the sampling already has; 4 levels would add more than it).
inline constexpr uint32_t kDefaultSoftLevels = 8;

// Nearest level of `fraction` (clamped to [0, 1]; NaN gives 0). `levels` in [kMinSoftLevels, kMaxSoftLevels].
inline uint32_t quantize(float fraction, uint32_t levels) {
  const float f = std::isnan(fraction) ? 0.0f : std::clamp(fraction, 0.0f, 1.0f);
  const float top = static_cast<float>(levels - 1);
  return std::min(levels - 1, static_cast<uint32_t>(std::floor(f * top + 0.5f)));
}

// The fraction a level stands for: level / (levels - 1).
inline float dequantize(uint32_t level, uint32_t levels) {
  return static_cast<float>(std::min(level, levels - 1)) / static_cast<float>(levels - 1);
}

// Gray code: adjacent levels differ in exactly one bit, so a penumbra that drifts by one level between frames
// changes one bit-plane, not several (helps an inter-frame bit-plane codec).
inline uint32_t gray_encode(uint32_t level) { return level ^ (level >> 1); }

inline uint32_t gray_decode(uint32_t gray) {
  for (uint32_t shift = 1; shift < 32; shift <<= 1) gray ^= gray >> shift;
  return gray;
}

}  // namespace dhr
