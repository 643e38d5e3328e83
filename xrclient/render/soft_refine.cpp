#include "render/soft_refine.hpp"

#include "shaders/shader_interface.h"

#include <algorithm>
#include <cmath>

namespace dhr::render {

using shader::kClientSoftRefineFields;
using shader::kClientSoftRefineNone;
using shader::kClientSoftRefineNoneAll;
using shader::kClientSoftRefineScale;

SoftWindow soft_window(const VisibilityBuffer& buffer, std::span<const uint8_t> row_valid, int i0, int j0) {
  SoftWindow w;
  for (int j = 0; j < 16; ++j) {
    const int a = i0 + j % 4 - 1, b = j0 + j / 4 - 1;
    if (a < 0 || b < 0 || a >= static_cast<int>(buffer.width) || b >= static_cast<int>(buffer.height)) continue;
    if (!row_valid.empty() && row_valid[static_cast<size_t>(b)] == 0) continue;
    w.masks[static_cast<size_t>(j)] = buffer.get(static_cast<uint32_t>(a), static_cast<uint32_t>(b));
    w.present |= 1u << j;
  }
  return w;
}

uint32_t soft_refine_bits(const VisibilityLayout& layout, uint32_t edge_lights) {
  uint32_t out = 0;
  for (uint32_t i = 0; i < layout.light_count; ++i)
    if (layout.is_soft(i) && ((edge_lights >> i) & 1u) == 0) out |= ((1u << layout.bits[i]) - 1u) << layout.offset[i];
  return out;
}

uint32_t soft_refine(const VisibilityLayout& layout, const SoftWindow& window, double fx, double fy, uint32_t value,
                     uint32_t edge_lights) {
  const uint32_t soft_bits = soft_refine_bits(layout, edge_lights);
  uint32_t and_m = 0xFFFFFFFFu, or_m = 0;
  for (int j = 0; j < 16; ++j) {
    if (((window.present >> j) & 1u) == 0) continue;
    and_m &= window.masks[static_cast<size_t>(j)];
    or_m |= window.masks[static_cast<size_t>(j)];
  }
  if (((and_m ^ or_m) & soft_bits) == 0) return kClientSoftRefineNoneAll;
  // The GPU computes in float: so does this, in the same order.
  const auto fxf = static_cast<float>(fx), fyf = static_cast<float>(fy);
  const float wx[4] = {1.0f - fxf, 2.0f - fxf, 1.0f + fxf, fxf};
  const float wy[4] = {1.0f - fyf, 2.0f - fyf, 1.0f + fyf, fyf};
  const auto steps = static_cast<float>(kDefaultSoftLevels - 1);
  uint32_t packed = kClientSoftRefineNoneAll, rank = 0;
  for (uint32_t i = 0; i < layout.light_count && rank < kClientSoftRefineFields; ++i) {
    if (!layout.is_soft(i)) continue;
    const uint32_t field = ((1u << layout.bits[i]) - 1u) << layout.offset[i];
    if (((edge_lights >> i) & 1u) != 0 || ((and_m ^ or_m) & field) == 0) {  // a field at one level keeps it
      ++rank;
      continue;
    }
    const float centre = layout.visibility(value, i);
    float sum = 0.0f, total = 0.0f;
    for (int j = 0; j < 16; ++j) {
      if (((window.present >> j) & 1u) == 0) continue;
      const float f = layout.visibility(window.masks[static_cast<size_t>(j)], i);
      if (std::abs(f - centre) * steps > 1.5f) continue;
      const float w = wx[j % 4] * wy[j / 4];
      sum += w * f;
      total += w;
    }
    const float share = total > 0.0f ? sum / total : centre;
    const auto byte = static_cast<uint32_t>(std::floor(std::clamp(share, 0.0f, 1.0f) *
                                                       static_cast<float>(kClientSoftRefineScale) + 0.5f));
    packed = (packed & ~(0xFFu << (8 * rank))) | (byte << (8 * rank));
    ++rank;
  }
  return packed;
}

uint32_t soft_refine_drop(const VisibilityLayout& layout, uint32_t packed, uint32_t bits) {
  uint32_t rank = 0;
  for (uint32_t i = 0; i < layout.light_count && rank < kClientSoftRefineFields; ++i) {
    if (!layout.is_soft(i)) continue;
    const uint32_t field = ((1u << layout.bits[i]) - 1u) << layout.offset[i];
    if ((bits & field) != 0) packed |= 0xFFu << (8 * rank);
    ++rank;
  }
  return packed;
}

double refined_share(uint32_t packed, uint32_t rank) {
  if (rank >= kClientSoftRefineFields) return -1.0;
  const uint32_t byte = (packed >> (8 * rank)) & 0xFFu;
  return byte == kClientSoftRefineNone ? -1.0 : static_cast<double>(byte) / kClientSoftRefineScale;
}

double shaded_share(const VisibilityLayout& layout, uint32_t mask, uint32_t packed, uint32_t light) {
  if (layout.is_soft(light)) {
    uint32_t rank = 0;
    for (uint32_t i = 0; i < light; ++i) rank += layout.is_soft(i) ? 1u : 0u;
    const double share = refined_share(packed, rank);
    if (share >= 0.0) return share;
  }
  return static_cast<double>(layout.visibility(mask, light));
}

}  // namespace dhr::render
