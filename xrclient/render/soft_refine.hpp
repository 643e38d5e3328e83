// Refined soft shares (WarpSettings::soft_refine): the CPU twin of shaders/client/bilinear_warp.h's
// warp_soft_blend, for the warp's CPU reference and for readers of the warp's soft target (dhr-eval).
//
// A soft field holds its share rounded to kClientSoftLevels levels, which bands a smooth penumbra into contours.
// Each received buffer's levels are reconstructed into band shares once (render/soft_bands.hpp); at a bilinear
// lookup the warp blends the used samples' band shares whose level lies within one level of the vote's (a jump of
// more, a contact shadow, is kept). The first kClientSoftRefineFields soft fields get a byte each (share x
// kClientSoftRefineScale, rounded); kClientSoftRefineNone marks a field without one (its level holds).
#pragma once
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

#include <array>
#include <cstdint>
#include <span>

namespace dhr::render {

// The bits of the soft fields the warp refines: every soft light's but those of `edge_lights` (bit i: light i).
uint32_t soft_refine_bits(const VisibilityLayout& layout, uint32_t edge_lights);

// The packed refined shares at a bilinear lookup: `masks` and `shares` (soft_band_shares of the source) of its
// 2x2 samples, `used` the samples the vote used, fx and fy the lookup's fractions past the first sample's centre
// (the bilinear weights, computed in float as the GPU does), `value` the vote's mask, `exact` the sample whose mask
// the vote took (an exact lookup: its share alone) or -1. Per soft field among the first kClientSoftRefineFields
// with a bit in `refine_bits` (soft_refine_bits): the weighted mean of the used samples' shares whose level lies
// within one level of the vote's (a sample's none byte: its level); none where no such sample has a band share or
// weighs anything.
uint32_t soft_blend(const VisibilityLayout& layout, const std::array<uint32_t, 4>& masks,
                    const std::array<uint32_t, 4>& shares, uint32_t used, double fx, double fy, uint32_t value,
                    int exact, uint32_t refine_bits);

// `packed` with the shares of the soft fields any of whose bits are in `bits` cleared (taken from the shadow maps).
uint32_t soft_refine_drop(const VisibilityLayout& layout, uint32_t packed, uint32_t bits);

// Soft field `rank`'s (0-based among the soft fields) refined share, or a negative value where there is none.
double refined_share(uint32_t packed, uint32_t rank);

// Light i's share as the client shades it: its refined share where it has one, else layout.visibility(mask, i).
double shaded_share(const VisibilityLayout& layout, uint32_t mask, uint32_t packed, uint32_t light);

}  // namespace dhr::render
