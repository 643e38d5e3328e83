// A light's field in a pixel's visibility mask (GLSL twin of visibility/visibility_layout.hpp, which derives the
// layout from the scene's lights): fields follow the lights' order from bit 0; a hard light's field is its bit
// (1 = lit), a soft light's kClientSoftBits bits hold the Gray code of its visibility quantized to
// kClientSoftLevels levels (visibility/soft_levels.hpp). The shaders get the layout as a mask of the soft lights
// (bit i: light i is soft), or per light (ClientShadowLight::mask_offset, mask_bits).
#ifndef DHR_VISIBILITY_FIELD_H
#define DHR_VISIBILITY_FIELD_H

#include "shaders/shader_interface.h"

// Width of light i's field.
uint field_bits(uint soft_lights, uint i) { return ((soft_lights >> i) & 1u) != 0u ? kClientSoftBits : 1u; }

// The share of the light a field says the point sees: the bit (hard), level / (levels - 1) (soft).
float field_visibility(uint mask, uint offset, uint bits) {
  const uint f = (mask >> offset) & ((1u << bits) - 1u);
  if (bits == 1u) return float(f);
  const uint level = f ^ (f >> 1u) ^ (f >> 2u);  // Gray decode (3 bits)
  return float(level) / float(kClientSoftLevels - 1u);
}

// The field (at its offset) for `fraction`: hard lit when fraction >= 0.5; soft: its nearest level, Gray-coded
// (soft_levels.hpp's quantize: floor(f * (levels - 1) + 0.5)).
uint field_from_fraction(float fraction, uint offset, uint bits) {
  if (bits == 1u) return fraction >= 0.5 ? 1u << offset : 0u;
  const float f = clamp(fraction, 0.0, 1.0);
  const uint level = min(kClientSoftLevels - 1u, uint(floor(f * float(kClientSoftLevels - 1u) + 0.5)));
  return (level ^ (level >> 1u)) << offset;
}

// Every light fully lit: all bits of a hard field, the top level's Gray code in a soft one. Without soft lights
// all 32 bits (what the passes used before soft fields existed).
uint fields_all_lit(uint soft_lights, uint light_count) {
  if (soft_lights == 0u) return 0xFFFFFFFFu;
  uint mask = 0u, offset = 0u;
  for (uint i = 0u; i < light_count; ++i) {
    const uint bits = field_bits(soft_lights, i);
    mask |= field_from_fraction(1.0, offset, bits);
    offset += bits;
  }
  return mask;
}

#endif  // DHR_VISIBILITY_FIELD_H
