#include "visibility/visibility_layout.hpp"

#include <stdexcept>
#include <string>

namespace dhr {

VisibilityLayout VisibilityLayout::for_lights(std::span<const bool> soft) {
  if (soft.size() > kMaxLights) {
    throw std::invalid_argument("visibility layout: " + std::to_string(soft.size()) + " lights (at most " +
                                std::to_string(kMaxLights) + ")");
  }
  VisibilityLayout layout;
  layout.light_count = static_cast<uint32_t>(soft.size());
  // Every light needs at least its bit: a soft light gets its levels while the lights after it still fit.
  uint32_t next = 0;
  for (uint32_t i = 0; i < layout.light_count; ++i) {
    const uint32_t lights_after = layout.light_count - i - 1;
    const bool room = next + kSoftLevelBits + lights_after <= 32;
    const uint32_t width = soft[i] && room ? kSoftLevelBits : 1;
    if (soft[i] && !room) ++layout.demoted;
    layout.offset[i] = static_cast<uint8_t>(next);
    layout.bits[i] = static_cast<uint8_t>(width);
    next += width;
  }
  return layout;
}

VisibilityLayout VisibilityLayout::hard(uint32_t light_count) {
  if (light_count > kMaxLights) {
    throw std::invalid_argument("visibility layout: " + std::to_string(light_count) + " lights (at most " +
                                std::to_string(kMaxLights) + ")");
  }
  VisibilityLayout layout;
  layout.light_count = light_count;
  for (uint32_t i = 0; i < light_count; ++i) {
    layout.offset[i] = static_cast<uint8_t>(i);
    layout.bits[i] = 1;
  }
  return layout;
}

uint32_t VisibilityLayout::total_bits() const {
  return light_count == 0 ? 0u : static_cast<uint32_t>(offset[light_count - 1]) + bits[light_count - 1];
}

bool VisibilityLayout::any_soft() const {
  for (uint32_t i = 0; i < light_count; ++i) {
    if (is_soft(i)) return true;
  }
  return false;
}

uint32_t VisibilityLayout::used_bits() const {
  const uint32_t n = total_bits();
  return n >= 32 ? 0xFFFFFFFFu : (1u << n) - 1u;
}

uint32_t VisibilityLayout::all_lit() const {
  uint32_t mask = 0;
  for (uint32_t i = 0; i < light_count; ++i) mask = with_visibility(mask, i, 1.0f);
  return mask;
}

float VisibilityLayout::visibility(uint32_t mask, uint32_t light) const {
  const uint32_t f = field(mask, light);
  if (!is_soft(light)) return static_cast<float>(f);
  return dequantize(gray_decode(f), kDefaultSoftLevels);
}

uint32_t VisibilityLayout::with_visibility(uint32_t mask, uint32_t light, float fraction) const {
  const uint32_t width_mask = ((1u << bits[light]) - 1u) << offset[light];
  const uint32_t value = is_soft(light) ? gray_encode(quantize(fraction, kDefaultSoftLevels))
                                        : (fraction >= 0.5f ? 1u : 0u);
  return (mask & ~width_mask) | (value << offset[light]);
}

}  // namespace dhr
