// Refined soft shares (WarpSettings::soft_refine): the CPU twin of shaders/client/bilinear_warp.h's
// warp_soft_refine, for the warp's CPU reference and for readers of the warp's soft target (dhr-eval).
//
// A soft field holds its share rounded to kClientSoftLevels levels, which bands a smooth penumbra into contours.
// At a bilinear lookup the warp takes, per soft field, the mean of the levels of the 4x4 old pixels around the
// lookup that lie within one level of the vote's, weighted by a tent of radius 2 old pixels centred on the lookup:
// where a smooth share crosses from one level to the next the neighbours on both sides say how far it lies between
// them. The first kClientSoftRefineFields soft fields get a byte each (share x kClientSoftRefineScale, rounded);
// kClientSoftRefineNone marks a field without one (its level holds).
#pragma once
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

#include <array>
#include <cstdint>
#include <span>

namespace dhr::render {

// The 4x4 old pixels around a bilinear lookup whose first sample is (i0, j0): pixel j is (i0 + j % 4 - 1,
// j0 + j / 4 - 1); `present` bit j where it lies in the buffer and its row arrived.
struct SoftWindow {
  std::array<uint32_t, 16> masks{};
  uint32_t present = 0;
};
SoftWindow soft_window(const VisibilityBuffer& buffer, std::span<const uint8_t> row_valid, int i0, int j0);

// The bits of the soft fields soft_refine refines: every soft light's but those of `edge_lights` (bit i: light i).
uint32_t soft_refine_bits(const VisibilityLayout& layout, uint32_t edge_lights);

// The packed refined shares (fx, fy: the lookup's fractions past the first sample's centre, in [0, 1); value: the
// vote's mask). None for soft fields beyond the first kClientSoftRefineFields, for those of `edge_lights` (bit i:
// light i; a sun's, soft_edge_light_mask), and for a field the present pixels hold at one level (its answer).
// The warp refines only lookups whose used 2x2 samples differ in soft_refine_bits.
uint32_t soft_refine(const VisibilityLayout& layout, const SoftWindow& window, double fx, double fy, uint32_t value,
                     uint32_t edge_lights = 0);

// `packed` with the shares of the soft fields any of whose bits are in `bits` cleared (taken from the shadow maps).
uint32_t soft_refine_drop(const VisibilityLayout& layout, uint32_t packed, uint32_t bits);

// Soft field `rank`'s (0-based among the soft fields) refined share, or a negative value where there is none.
double refined_share(uint32_t packed, uint32_t rank);

// Light i's share as the client shades it: its refined share where it has one, else layout.visibility(mask, i).
double shaded_share(const VisibilityLayout& layout, uint32_t mask, uint32_t packed, uint32_t light);

}  // namespace dhr::render
