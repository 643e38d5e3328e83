// Band shares (WarpSettings::soft_refine): a received buffer's soft levels reconstructed into a continuous share per
// traced pixel, once per buffer (WarpSourceBuffers::upload for the GPU passes, the warp's CPU reference).
//
// A soft field holds its share rounded to kDefaultSoftLevels levels, which bands a smooth penumbra into contours (a
// 6 cm bulb's penumbra covers the area room's ceiling in bands 10-30 pixels wide at 320x240, their boundaries
// jagged). Where the share varies slowly, the levels around a pixel say where it lies between two
// levels: a pixel of level n among pixels of n - 1 and n + 1 in proportion lies as far between. The band share of a
// pixel of level n is the mean of the levels n - 1, n and n + 1 over the arrived pixels of the window around it
// (pixels further than one level, a contact shadow or another surface, are left out), clamped to n +- 1/2 (the
// interval its level stands for): the reconstruction never leaves what the server sent. The bottom and top levels
// keep theirs (below). The counts come from box sums of eight indicator images (arrived; level at least k, k = 1..7),
// a running sum along the rows, then along the columns, so the cost does not grow with the radius. The radius is a
// fixed share of the buffer's width (soft_band_radius: the bands are a fixed angle of the view, whatever the
// resolution). The table is made on the GPU by render/soft_band_pass.hpp for the warp passes (kClientSourceHasShares),
// by soft_band_table here for the warp's CPU reference and the tests; both give the same bytes.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "shaders/shader_interface.h"
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

namespace dhr::render {

// The window's radius for a buffer `width` pixels wide: width / kSoftBandRadiusDivisor, rounded, at least 1 and at
// most kMaxSoftBandRadius (7 pixels at 340: a 320-pixel eye's buffer with dhr-eval's guard band; 40 at 1984).
inline constexpr uint32_t kSoftBandRadiusDivisor = 50;
// The window's pixel counts fit 16 bits: its side (2 rc + 1) c is at most 2 radius + 2 c <= 2.5 radius <= 255.
inline constexpr uint32_t kMaxSoftBandRadius = 100;
uint32_t soft_band_radius(uint32_t width);

// The window counts cells of c x c pixels, c the largest power of two at most radius / kSoftBandCellsPerRadius and at
// least kMinSoftBandCell (a power of two: the GPU finds a sample's cell by shifts): the window is the (2 rc + 1)^2
// cells around the pixel's cell, rc = radius / c rounded. At radius 7 (a 320-pixel eye) cells are 2 x 2 pixels, at 40
// (1984) 8 x 8. Every pixel of a cell at the same level has the same band share, so the table holds one byte per cell
// and level: the cost per pixel is one counter update, and the GPU reads a sample's share from its cell. (On the
// area room, 6 frames of User1 at 320x240, cells of 1 and 3 pixels at radius 7 gave visibility_error 0.01075 and
// 0.01082.)
inline constexpr uint32_t kSoftBandCellsPerRadius = 4;
inline constexpr uint32_t kMinSoftBandCell = 2;
uint32_t soft_band_cell(uint32_t radius);

// The cells of a buffer's table at a window radius: their side (soft_band_cell), cells per row and column, and the
// window's reach: the cells within `reach` cells of a pixel's cell along each axis (radius / cell, rounded, at least
// 1). Throws std::invalid_argument for a radius outside 1..kMaxSoftBandRadius.
struct SoftBandShape {
  uint32_t cell = 1;
  uint32_t columns = 0;
  uint32_t rows = 0;
  uint32_t reach = 1;
};
SoftBandShape soft_band_shape(uint32_t width, uint32_t height, uint32_t radius);

// The band shares of a buffer: per cell (row-major, `columns` per row) kClientSoftBandCellWords words, two per
// refined field rank r (the first kClientSoftRefineFields soft fields): word 2 r + n / 4, byte n % 4 holds the share
// of a pixel at level n, x kClientSoftRefineScale rounded; kClientSoftRefineNone for the bottom and top levels (most
// of their pixels are fully hidden or fully lit, exactly 0 or 1: they keep their level), for a level no arrived pixel
// of the cell holds and for fields without a share.
struct SoftBandTable {
  uint32_t cell = 1;     // pixels per cell side (a power of two)
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
