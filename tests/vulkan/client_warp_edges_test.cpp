// The warp's edge band marks (render/warp_edges.hpp) against a direct scan of every pixel's window. The warp's use
// of them is compared with the CPU reference in client_forward_test.cpp, client_forward_depth_test.cpp and
// client_warp_full_test.cpp (the shipped settings carry the band).
#include "render/warp_edges.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace dhr::render {
namespace {

// Blocks, a one-pixel line and a lone pixel, in several bits.
VisibilityBuffer pattern(uint32_t width, uint32_t height, uint32_t lights) {
  VisibilityBuffer b = VisibilityBuffer::create(width, height, lights);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      uint32_t m = b.light_bits();
      if ((x / 7 + y / 5) % 2 == 0) m &= ~1u;  // light 0: a checkerboard of 7x5 blocks
      if (x == 11) m &= ~2u;                   // light 1: a thin vertical shadow
      if (x == 20 && y == 9) m &= ~4u;         // light 2: one pixel
      if (lights > 8 && y > 15) m &= ~(1u << (lights - 1));  // the top bit of wider masks
      b.set(x, y, m);
    }
  }
  return b;
}

uint32_t scanned(const VisibilityBuffer& b, const std::vector<uint8_t>& rows, int x, int y, int band, uint32_t bits) {
  if (!rows.empty() && rows[static_cast<size_t>(y)] == 0) return 0;
  uint32_t and_m = 0xFFFFFFFFu, or_m = 0u;
  for (int v = y - band; v <= y + band; ++v) {
    if (v < 0 || v >= static_cast<int>(b.height) || (!rows.empty() && rows[static_cast<size_t>(v)] == 0)) continue;
    for (int u = x - band; u <= x + band; ++u) {
      if (u < 0 || u >= static_cast<int>(b.width)) continue;
      const uint32_t m = b.get(static_cast<uint32_t>(u), static_cast<uint32_t>(v));
      and_m &= m;
      or_m |= m;
    }
  }
  return (and_m ^ or_m) & bits;
}

TEST(WarpEdges, MarksEqualAScanOfEveryWindow) {
  for (const uint32_t lights : {3u, 12u, 24u}) {
    const VisibilityBuffer b = pattern(37, 23, lights);
    std::vector<uint8_t> rows(b.height, 1);
    rows[4] = rows[5] = rows[17] = 0;
    const uint32_t bits = b.light_bits() & ~2u;  // light 1 stands for a soft field: never marked
    for (const std::vector<uint8_t>& valid : {std::vector<uint8_t>{}, rows}) {
      for (uint32_t band = 0; band <= 3; ++band) {
        SCOPED_TRACE(testing::Message() << lights << " lights, band " << band << ", rows lost: " << !valid.empty());
        const VisibilityBuffer marks = edge_band_marks(b, valid, band, bits);
        ASSERT_EQ(marks.width, b.width);
        ASSERT_EQ(marks.mask_bits, b.mask_bits);
        size_t marked = 0;
        for (uint32_t y = 0; y < b.height; ++y) {
          for (uint32_t x = 0; x < b.width; ++x) {
            const uint32_t want = band == 0 ? 0u : scanned(b, valid, static_cast<int>(x), static_cast<int>(y),
                                                           static_cast<int>(band), bits);
            ASSERT_EQ(marks.get(x, y), want) << x << "," << y;
            marked += want != 0 ? 1 : 0;
          }
        }
        if (band > 0) {
          EXPECT_GT(marked, 0u);
        }
      }
    }
  }
}

TEST(WarpEdges, TheBandWidensAnEdgeByItsWidthAndSkipsLostRows) {
  VisibilityBuffer b = VisibilityBuffer::create(16, 8, 1);
  for (uint32_t y = 0; y < 8; ++y) {
    for (uint32_t x = 0; x < 16; ++x) b.set(x, y, x < 8 ? 1u : 0u);  // the edge between columns 7 and 8
  }
  const VisibilityBuffer two = edge_band_marks(b, {}, 2, 1u);
  for (uint32_t x = 0; x < 16; ++x) EXPECT_EQ(two.get(x, 3), x >= 6 && x <= 9 ? 1u : 0u) << x;
  // A row that did not arrive is neither marked nor read.
  std::vector<uint8_t> rows(8, 1);
  rows[3] = 0;
  b.set(0, 3, 0u);  // an edge in the lost row only
  const VisibilityBuffer lost = edge_band_marks(b, rows, 2, 1u);
  for (uint32_t x = 0; x < 16; ++x) EXPECT_EQ(lost.get(x, 3), 0u) << x;
  EXPECT_EQ(lost.get(0, 2), 0u);
}

TEST(WarpEdges, RefusesABandAboveTheLimitAndRowsOfAnotherLength) {
  const VisibilityBuffer b = VisibilityBuffer::create(8, 4, 2);
  EXPECT_THROW(edge_band_marks(b, {}, kMaxEdgeBand + 1, 3u), std::invalid_argument);
  const std::vector<uint8_t> rows(3, 1);
  EXPECT_THROW(edge_band_marks(b, rows, 1, 3u), std::invalid_argument);
  EXPECT_NO_THROW(edge_band_marks(b, {}, kMaxEdgeBand, 3u));
}

TEST(WarpEdges, HardFieldBitsLeaveSoftFieldsOut) {
  const bool soft[] = {false, true, false};
  const VisibilityLayout layout = VisibilityLayout::for_lights(soft);
  // Light 0 at bit 0, light 1's three bits 1-3, light 2 at bit 4.
  EXPECT_EQ(hard_field_bits(layout), 0b10001u);
  EXPECT_EQ(hard_field_bits(VisibilityLayout::hard(3)), 0b111u);
}

}  // namespace
}  // namespace dhr::render
