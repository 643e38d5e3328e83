// Band shares (WarpSettings::soft_refine): a received buffer's soft levels reconstructed into a continuous share per
// traced pixel, once per buffer (WarpSourceBuffers::upload for the GPU passes, the warp's CPU reference).
//
// A soft field holds its share rounded to kDefaultSoftLevels levels, which bands a smooth penumbra into contours (a
// 6 cm bulb's penumbra covers the area room's ceiling in bands 10-30 pixels wide at 320x240, their boundaries
// jagged by the sampling). Where the share varies slowly, the levels around a pixel say where it lies between two
// levels: a pixel of level n among pixels of n - 1 and n + 1 in proportion lies as far between. The band share of a
// pixel of level n is the mean of the levels n - 1, n and n + 1 over the arrived pixels of the window around it
// (pixels further than one level, a contact shadow or another surface, are left out), clamped to n +- 1/2 (the
// interval its level stands for) and to [0, levels - 1]: the reconstruction never leaves what the server sent. The
// counts come from box sums of eight indicator images (arrived; level at least k, k = 1..7), a running sum along
// the rows, then along the columns, so the cost does not grow with the radius. The radius is a fixed share of the
// buffer's width (soft_band_radius: the bands are a fixed angle of the view, whatever the resolution). The CPU
// computes the table once per received buffer; the GPU passes read it (kClientSourceHasShares).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "shaders/shader_interface.h"
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

namespace dhr::render {

// The window's radius for a buffer `width` pixels wide: width / kSoftBandRadiusDivisor, rounded, at least 1 and at
// most kMaxSoftBandRadius (8 pixels at 384: a 320-pixel eye's buffer with its guard band; 40 at 1984).
inline constexpr uint32_t kSoftBandRadiusDivisor = 50;
inline constexpr uint32_t kMaxSoftBandRadius = 127;  // the window's counts fit 16 bits
uint32_t soft_band_radius(uint32_t width);

// The window counts cells of c x c pixels, c = radius / kSoftBandCellsPerRadius (at least 1): it is the (2 rc + 1)^2
// cells around the pixel's cell, rc = radius / c rounded. At radius 8 (a 320-pixel eye) cells are 2 x 2 pixels, at 40
// (1984) 10 x 10. Every pixel of a cell at the same level has the same band share, so the table holds one byte per
// cell and level: the cost per pixel is one counter update, and the GPU reads a sample's share from its cell. (On
// the area room, 6 frames of User1 at 320x240, cells of 1, 2 and 4 pixels gave visibility_error 0.01075, 0.01075 and
// 0.01082.)
inline constexpr uint32_t kSoftBandCellsPerRadius = 4;
uint32_t soft_band_cell(uint32_t radius);

// The band shares of a buffer: per cell (row-major, `columns` per row) kClientSoftBandCellWords words, two per
// refined field rank r (the first kClientSoftRefineFields soft fields): word 2 r + n / 4, byte n % 4 holds the share
// of a pixel at level n, x kClientSoftRefineScale rounded; kClientSoftRefineNone for a level no arrived pixel of the
// cell holds and for fields without a share.
struct SoftBandTable {
  uint32_t cell = 1;     // pixels per cell side
  uint32_t columns = 0;  // cells per row
  uint32_t rows = 0;
  std::vector<uint32_t> words;
};

// The table of `buffer`'s soft fields with a bit in `bits` (soft_refine_bits). `row_valid`: empty (every row
// arrived) or one entry per row, 0 = missing (its pixels count for nothing). Throws std::invalid_argument for a
// row_valid of another length or a radius outside 1..kMaxSoftBandRadius.
SoftBandTable soft_band_table(const VisibilityLayout& layout, const VisibilityBuffer& buffer,
                              std::span<const uint8_t> row_valid, uint32_t bits, uint32_t radius);

// The packed band shares (kClientSoftRefine*) of pixel (x, y) of the table's buffer, whose mask is `mask`: per
// soft field rank, its level's byte in the pixel's cell.
uint32_t soft_band_shares_at(const SoftBandTable& table, const VisibilityLayout& layout, uint32_t x, uint32_t y,
                             uint32_t mask);

}  // namespace dhr::render
