#include "render/soft_bands.hpp"

#include "shaders/shader_interface.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <stdexcept>

namespace dhr::render {

namespace {

using shader::kClientSoftBandCellWords;
using shader::kClientSoftRefineFields;
using shader::kClientSoftRefineNoneAll;
using shader::kClientSoftRefineScale;

constexpr uint32_t kNoLevel = 8;  // a pixel whose row did not arrive

// A pixel's counters, 16 bits each: lane 0 whether it arrived, lane k (1-7) whether its level is at least k; `lo`
// holds lanes 0-3, `hi` lanes 4-7.
struct Lanes {
  uint64_t lo = 0;
  uint64_t hi = 0;
};
Lanes lanes_of(uint32_t level) {
  Lanes l;
  if (level == kNoLevel) return l;
  for (uint32_t k = 0; k < 8; ++k) {
    if (level < k) break;
    (k < 4 ? l.lo : l.hi) |= uint64_t{1} << (16 * (k % 4));
  }
  return l;
}
uint32_t lane(const Lanes& l, uint32_t k) {
  if (k > 7) return 0;
  return static_cast<uint32_t>(((k < 4 ? l.lo : l.hi) >> (16 * (k % 4))) & 0xFFFFu);
}

// The band share of a pixel at level n whose window holds `win`: the mean of the levels n - 1, n and n + 1 over the
// window's arrived pixels (at level k: lane k less lane k + 1), within n +- 1/2, as a byte. In integers (twice the
// mean, over the pixels within one level), as soft_bands.comp computes it: the GPU's table has the same bytes.
uint8_t share_byte(const Lanes& win, uint32_t n) {
  constexpr uint32_t kTop = kDefaultSoftLevels - 1;
  const uint32_t from_below = lane(win, n > 0 ? n - 1 : 0), at_n = lane(win, n);
  const uint32_t above = lane(win, n + 1), beyond = lane(win, n + 2);
  const uint32_t below = n > 0 ? from_below - at_n : 0u;
  const uint32_t near = from_below - beyond;  // 0: no pixel of the window within one level (none of level n)
  uint32_t twice = 2 * n, d = 1;              // the level itself
  if (near > 0) {
    const auto nn = static_cast<int64_t>(near);
    const int64_t s = 2 * (static_cast<int64_t>(n) * nn + static_cast<int64_t>(above - beyond) - below);
    twice = static_cast<uint32_t>(std::clamp(s, std::max<int64_t>(0, (2 * n - int64_t{1}) * nn),
                                             std::min<int64_t>(2 * kTop * nn, (2 * n + int64_t{1}) * nn)));
    d = near;
  }
  return static_cast<uint8_t>((twice * kClientSoftRefineScale + kTop * d) / (2 * kTop * d));
}

}  // namespace

uint32_t soft_band_radius(uint32_t width) {
  return std::clamp((width + kSoftBandRadiusDivisor / 2) / kSoftBandRadiusDivisor, 1u, kMaxSoftBandRadius);
}

uint32_t soft_band_cell(uint32_t radius) {
  return std::bit_floor(std::max(kMinSoftBandCell, radius / kSoftBandCellsPerRadius));
}

SoftBandShape soft_band_shape(uint32_t width, uint32_t height, uint32_t radius) {
  if (radius < 1 || radius > kMaxSoftBandRadius) {
    throw std::invalid_argument("band shares: window radius " + std::to_string(radius) + " outside 1.." +
                                std::to_string(kMaxSoftBandRadius));
  }
  // Cells of c x c pixels; the window is (2 rc + 1)^2 cells around the pixel's cell, at most 255^2 pixels.
  static_assert(2 * kMaxSoftBandRadius + 2 * (kMaxSoftBandRadius / kSoftBandCellsPerRadius) <= 255,
                "the window's counts fit the 16-bit lanes");
  SoftBandShape shape;
  shape.cell = soft_band_cell(radius);
  shape.reach = std::max(1u, (radius + shape.cell / 2) / shape.cell);
  shape.columns = (width + shape.cell - 1) / shape.cell;
  shape.rows = (height + shape.cell - 1) / shape.cell;
  return shape;
}

SoftBandTable soft_band_table(const VisibilityLayout& layout, const VisibilityBuffer& buffer,
                              std::span<const uint8_t> row_valid, uint32_t bits, uint32_t radius) {
  if (!row_valid.empty() && row_valid.size() != buffer.height) {
    throw std::invalid_argument("soft_band_table: row_valid holds " + std::to_string(row_valid.size()) +
                                " rows, the buffer " + std::to_string(buffer.height));
  }
  const uint32_t w = buffer.width, h = buffer.height;
  SoftBandTable t;
  const SoftBandShape shape = soft_band_shape(w, h, radius);
  const uint32_t c = shape.cell, rc = shape.reach;
  t.cell = c;
  t.columns = shape.columns;
  t.rows = shape.rows;
  const uint32_t cw = t.columns, ch = t.rows;
  t.words.assign(size_t{cw} * ch * kClientSoftBandCellWords, kClientSoftRefineNoneAll);
  std::array<Lanes, kNoLevel + 1> table{};
  for (uint32_t l = 0; l <= kNoLevel; ++l) table[l] = lanes_of(l);
  std::vector<Lanes> cells(size_t{cw} * ch), rows(size_t{cw} * ch), window(cw);
  std::vector<uint8_t> present(size_t{cw} * ch);  // bit n: a pixel of the cell holds level n
  const auto r = static_cast<int64_t>(rc);
  const uint32_t mask_bytes = buffer.bytes_per_mask();
  uint32_t rank = 0;
  for (uint32_t i = 0; i < layout.light_count && rank < kClientSoftRefineFields; ++i) {
    if (!layout.is_soft(i)) continue;
    const uint32_t field_rank = rank++;
    const uint32_t field = ((1u << layout.bits[i]) - 1u) << layout.offset[i];
    if ((bits & field) == 0) continue;
    std::array<uint8_t, 1u << kSoftLevelBits> level_of{};
    for (uint32_t g = 0; g < level_of.size(); ++g) level_of[g] = static_cast<uint8_t>(gray_decode(g));
    const uint32_t offset = layout.offset[i], low = (1u << layout.bits[i]) - 1u;
    // Each cell's counters and the levels its pixels hold (rows that did not arrive count for nothing).
    std::fill(cells.begin(), cells.end(), Lanes{});
    std::fill(present.begin(), present.end(), uint8_t{0});
    for (uint32_t y = 0; y < h; ++y) {
      if (!row_valid.empty() && row_valid[y] == 0) continue;
      Lanes* cell = cells.data() + size_t{y / c} * cw;
      uint8_t* held = present.data() + size_t{y / c} * cw;
      const uint8_t* src = buffer.data.data() + size_t{y} * w * mask_bytes;
      const auto count = [&]<typename Mask>() {
        for (uint32_t x0 = 0, cx = 0; x0 < w; x0 += c, ++cx) {
          Lanes sum = cell[cx];
          uint32_t levels = held[cx];
          for (uint32_t x = x0; x < std::min(w, x0 + c); ++x) {
            Mask m;
            std::memcpy(&m, src + size_t{x} * sizeof(Mask), sizeof(Mask));  // little-endian, as the buffers are
            const uint8_t n = level_of[(static_cast<uint32_t>(m) >> offset) & low];
            sum.lo += table[n].lo;
            sum.hi += table[n].hi;
            levels |= 1u << n;
          }
          cell[cx] = sum;
          held[cx] = static_cast<uint8_t>(levels);
        }
      };
      if (mask_bytes == 1) {
        count.operator()<uint8_t>();
      } else if (mask_bytes == 2) {
        count.operator()<uint16_t>();
      } else {
        count.operator()<uint32_t>();
      }
    }
    // The row pass over the cells: a running sum over [x - rc, x + rc] (clipped at the edges).
    for (uint32_t y = 0; y < ch; ++y) {
      const Lanes* in = cells.data() + size_t{y} * cw;
      Lanes* row = rows.data() + size_t{y} * cw;
      Lanes sum;
      for (int64_t x = 0; x < std::min<int64_t>(r, cw); ++x) {
        sum.lo += in[x].lo;
        sum.hi += in[x].hi;
      }
      for (int64_t x = 0; x < cw; ++x) {
        if (x + r < cw) {
          sum.lo += in[x + r].lo;
          sum.hi += in[x + r].hi;
        }
        if (x - r - 1 >= 0) {
          sum.lo -= in[x - r - 1].lo;
          sum.hi -= in[x - r - 1].hi;
        }
        row[x] = sum;
      }
    }
    // The column pass, a row of cells at a time (window: the row sums of cell rows [y - rc, y + rc]), and the
    // bytes of the levels each cell holds.
    std::fill(window.begin(), window.end(), Lanes{});
    const auto add_row = [&](int64_t y, bool add) {
      const Lanes* row = rows.data() + static_cast<size_t>(y) * cw;
      for (uint32_t x = 0; x < cw; ++x) {
        window[x].lo = add ? window[x].lo + row[x].lo : window[x].lo - row[x].lo;
        window[x].hi = add ? window[x].hi + row[x].hi : window[x].hi - row[x].hi;
      }
    };
    for (int64_t y = 0; y < std::min<int64_t>(r, ch); ++y) add_row(y, true);
    for (int64_t cy = 0; cy < ch; ++cy) {
      if (cy + r < ch) add_row(cy + r, true);
      if (cy - r - 1 >= 0) add_row(cy - r - 1, false);
      for (uint32_t cx = 0; cx < cw; ++cx) {
        const size_t cell = static_cast<size_t>(cy) * cw + cx;
        uint32_t* words = t.words.data() + cell * kClientSoftBandCellWords + 2 * field_rank;
        // The top and bottom levels keep theirs (none: the sample's level): most of their pixels are fully lit or
        // fully hidden, exactly 1 or 0, where any pull is an error.
        constexpr uint32_t kMiddle = ((1u << kDefaultSoftLevels) - 1u) & ~1u & ~(1u << (kDefaultSoftLevels - 1));
        for (uint32_t levels = present[cell] & kMiddle; levels != 0; levels &= levels - 1) {
          const auto n = static_cast<uint32_t>(std::countr_zero(levels));
          const uint32_t shift = 8 * (n % 4);
          words[n / 4] = (words[n / 4] & ~(0xFFu << shift)) | (uint32_t{share_byte(window[cx], n)} << shift);
        }
      }
    }
  }
  return t;
}

uint32_t soft_band_shares_at(const SoftBandTable& table, const VisibilityLayout& layout, uint32_t x, uint32_t y,
                             uint32_t mask) {
  const size_t cell = size_t{y / table.cell} * table.columns + x / table.cell;
  const uint32_t* words = table.words.data() + cell * kClientSoftBandCellWords;
  uint32_t packed = kClientSoftRefineNoneAll, rank = 0;
  for (uint32_t i = 0; i < layout.light_count && rank < kClientSoftRefineFields; ++i) {
    if (!layout.is_soft(i)) continue;
    const uint32_t n = gray_decode(layout.field(mask, i));
    const uint32_t byte = (words[2 * rank + n / 4] >> (8 * (n % 4))) & 0xFFu;
    packed = (packed & ~(0xFFu << (8 * rank))) | (byte << (8 * rank));
    ++rank;
  }
  return packed;
}

}  // namespace dhr::render
