// Where each light's visibility sits in a pixel's mask. A punctual light (hard shadows) takes one bit: 1 = lit.
// A light with an extent (soft shadows: sphere, rect, disk, sun disk) takes kSoftLevelBits bits holding the
// Gray code (soft_levels.hpp) of its visibility quantized to kDefaultSoftLevels levels: level / (levels - 1) is
// the share of the light the surface point sees. Fields follow the lights' order, the first at bit 0, each
// after the previous one. Both ends derive the layout from the scene's lights (the scene hash is checked at
// the handshake), so it never travels. Up to 32 bits: soft lights that would overflow them take one bit (hard,
// traced to the light's centre) and `demoted` counts them, so the caller can warn, naming them.
// With no soft light the layout is one bit per light, exactly the hard-shadow masks of before.
#pragma once
#include <array>
#include <cstdint>
#include <span>

#include "visibility/soft_levels.hpp"
#include "visibility/visibility.hpp"

namespace dhr {

inline constexpr uint32_t kSoftLevelBits = 3;  // kDefaultSoftLevels = 8 levels
static_assert((1u << kSoftLevelBits) == kDefaultSoftLevels, "a soft light's field holds every level");

struct VisibilityLayout {
  uint32_t light_count = 0;
  std::array<uint8_t, kMaxLights> offset{};  // first bit of light i's field
  std::array<uint8_t, kMaxLights> bits{};    // 1 (hard) or kSoftLevelBits (soft)
  uint32_t demoted = 0;                      // soft lights given one bit for lack of room

  // soft[i]: light i has an extent. Throws std::invalid_argument for more than kMaxLights lights.
  static VisibilityLayout for_lights(std::span<const bool> soft);
  // One bit per light: the hard-shadow layout.
  static VisibilityLayout hard(uint32_t light_count);

  uint32_t total_bits() const;
  bool is_soft(uint32_t light) const { return bits[light] > 1; }
  bool any_soft() const;
  // The mask width that holds total_bits().
  MaskWidth mask_width() const { return mask_width_for_light_count(total_bits()); }
  // Every bit a mask may have set ((1 << total_bits()) - 1).
  uint32_t used_bits() const;
  // Every light fully lit: a hard light's bit, the top level's Gray code in a soft field.
  uint32_t all_lit() const;
  // Light i's field in `mask` (its Gray code for a soft light, the bit for a hard one).
  uint32_t field(uint32_t mask, uint32_t light) const { return (mask >> offset[light]) & ((1u << bits[light]) - 1u); }
  // The share of light i the mask says the point sees: 0 or 1 for a hard light, level / (levels - 1) for a soft
  // one.
  float visibility(uint32_t mask, uint32_t light) const;
  // `mask` with light i's field set to `fraction` (a hard light: lit when fraction >= 0.5; a soft light: its
  // nearest level, Gray-coded).
  uint32_t with_visibility(uint32_t mask, uint32_t light, float fraction) const;

  bool operator==(const VisibilityLayout&) const = default;
};

}  // namespace dhr
