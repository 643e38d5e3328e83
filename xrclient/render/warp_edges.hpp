// The warp's edge band (WarpSettings::edge_band): a traced buffer's shadow edges, widened, so that the warp takes the
// client's shadow maps wherever a hard light's edge lies near a lookup, not only where its 2x2 samples disagree.
//
// Between traced pixels a shadow edge is known only to a traced pixel's spacing, and at a lookup that lies off every
// traced pixel centre (any head motion) the bilinear vote puts the edge up to that far from where it is; a shadow map
// finer than a display pixel puts it within a texel. Where all four samples agree, the edge may still pass between
// them and the lookup when it bends, or when a thin shadow (a chair leg's) falls between the traced pixel centres.
// The band marks, per traced pixel, the hard-light bits on which the arrived traced pixels within `band` pixels
// (Chebyshev) of it do not all agree; the warp treats a bit any used sample's band marks as undecided (the shadow
// maps decide it). Soft lights keep their own rule (kClientWarpSoftEdgeSpread): the band leaves their fields alone.
//
// The GPU passes read these per-pixel marks, uploaded after the masks (WarpSourceBuffers::upload); the CPU
// reference (warp_reference.cpp) scans each sample's window itself, the exhaustive definition.
#pragma once
#include <cstdint>
#include <span>

#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

namespace dhr::render {

// The bits of the layout's hard lights' fields (one bit each; soft fields excluded).
uint32_t hard_field_bits(const VisibilityLayout& layout);

// Per pixel of `buffer` (same size and mask width): the bits of `bits` on which the arrived pixels within `band`
// (Chebyshev) of it, itself included, do not all agree; 0 for pixels whose own row did not arrive and for band 0.
// `row_valid`: empty (every row arrived) or one entry per row, 0 = missing. Separable: a row pass and a column
// pass of AND / OR over 2 band + 1 pixels each. Throws std::invalid_argument for a band above kMaxEdgeBand or a
// row_valid of another length.
inline constexpr uint32_t kMaxEdgeBand = 8;
VisibilityBuffer edge_band_marks(const VisibilityBuffer& buffer, std::span<const uint8_t> row_valid, uint32_t band,
                                 uint32_t bits);

}  // namespace dhr::render
