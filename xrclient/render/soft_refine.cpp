#include "render/soft_refine.hpp"

#include "shaders/shader_interface.h"

#include <algorithm>
#include <cmath>

namespace dhr::render {

using shader::kClientSoftRefineFields;
using shader::kClientSoftRefineNone;
using shader::kClientSoftRefineNoneAll;
using shader::kClientSoftRefineScale;

uint32_t soft_refine_bits(const VisibilityLayout& layout, uint32_t edge_lights) {
  uint32_t out = 0;
  for (uint32_t i = 0; i < layout.light_count; ++i)
    if (layout.is_soft(i) && ((edge_lights >> i) & 1u) == 0) out |= ((1u << layout.bits[i]) - 1u) << layout.offset[i];
  return out;
}

uint32_t soft_blend(const VisibilityLayout& layout, const std::array<uint32_t, 4>& masks,
                    const std::array<uint32_t, 4>& shares, uint32_t used, double fx, double fy, uint32_t value,
                    int exact, uint32_t refine_bits) {
  // The GPU computes in float: so does this, in the same order.
  const auto fxf = static_cast<float>(fx), fyf = static_cast<float>(fy);
  const auto steps = static_cast<float>(kDefaultSoftLevels - 1);
  uint32_t packed = kClientSoftRefineNoneAll, rank = 0;
  for (uint32_t i = 0; i < layout.light_count && rank < kClientSoftRefineFields; ++i) {
    if (!layout.is_soft(i)) continue;
    const uint32_t shift = 8 * rank++;
    const uint32_t field = ((1u << layout.bits[i]) - 1u) << layout.offset[i];
    if ((field & refine_bits) == 0) continue;
    const float centre = layout.visibility(value, i);
    float sum = 0.0f, total = 0.0f;
    bool shared = false;
    for (int k = 0; k < 4; ++k) {
      if (((used >> k) & 1u) == 0 || (exact >= 0 && k != exact)) continue;
      const float f = layout.visibility(masks[static_cast<size_t>(k)], i);
      if (std::abs(f - centre) * steps > 1.5f) continue;
      const uint32_t byte = (shares[static_cast<size_t>(k)] >> shift) & 0xFFu;
      const float share = byte == kClientSoftRefineNone ? f : static_cast<float>(byte) / kClientSoftRefineScale;
      const float w = exact >= 0 ? 1.0f : ((k & 1) != 0 ? fxf : 1.0f - fxf) * ((k >> 1) != 0 ? fyf : 1.0f - fyf);
      sum += w * share;
      total += w;
      shared = shared || byte != kClientSoftRefineNone;
    }
    if (!shared || !(total > 0.0f)) continue;  // no used sample has a band share: the vote's level holds
    const auto byte = static_cast<uint32_t>(std::floor(std::clamp(sum / total, 0.0f, 1.0f) *
                                                       static_cast<float>(kClientSoftRefineScale) + 0.5f));
    packed = (packed & ~(0xFFu << shift)) | (byte << shift);
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
