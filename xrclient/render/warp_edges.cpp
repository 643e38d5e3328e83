#include "render/warp_edges.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace dhr::render {
namespace {

static_assert(std::endian::native == std::endian::little, "the marks are stored as little-endian integers");

// AND and OR are bitwise, so the windows run on the masks' bytes whatever their width (a neighbour d pixels away is
// d x bytes-per-mask bytes away) in plain byte loops the compiler vectorizes; only the last step, keeping `bits`,
// needs the width.
template <typename T>
void keep_bits(const uint8_t* and_bytes, const uint8_t* or_bytes, size_t count, uint32_t bits, uint8_t* out) {
  const T keep = static_cast<T>(bits);
  for (size_t i = 0; i < count; ++i) {
    T a, o;
    std::memcpy(&a, and_bytes + i * sizeof(T), sizeof(T));
    std::memcpy(&o, or_bytes + i * sizeof(T), sizeof(T));
    const T m = static_cast<T>((a ^ o) & keep);
    std::memcpy(out + i * sizeof(T), &m, sizeof(T));
  }
}

// One row's window AND / OR over the pixels within R (bpm bytes each) of each pixel, within the row: the interior
// in one fused pass (R fixed, so the compiler unrolls the window and vectorizes the bytes), the R pixels at either
// end clipped to the row.
template <int R>
void row_window(const uint8_t* __restrict m, size_t row_bytes, size_t bpm, uint8_t* __restrict a,
                uint8_t* __restrict o) {
  const size_t reach = static_cast<size_t>(R) * bpm;
  const auto clipped = [&](size_t i) {  // byte i of a pixel within R of an end
    const size_t lane = i % bpm, pixel = i / bpm, pixels = row_bytes / bpm;
    const size_t first = pixel >= static_cast<size_t>(R) ? pixel - R : 0;
    const size_t last = std::min(pixels - 1, pixel + static_cast<size_t>(R));
    uint8_t and_v = 0xFF, or_v = 0;
    for (size_t p = first; p <= last; ++p) {
      and_v &= m[p * bpm + lane];
      or_v |= m[p * bpm + lane];
    }
    a[i] = and_v;
    o[i] = or_v;
  };
  if (row_bytes <= 2 * reach) {
    for (size_t i = 0; i < row_bytes; ++i) clipped(i);
    return;
  }
  for (size_t i = 0; i < reach; ++i) clipped(i);
  for (size_t i = reach; i < row_bytes - reach; ++i) {
    uint8_t and_v = m[i], or_v = m[i];
    for (int d = 1; d <= R; ++d) {
      const size_t s = static_cast<size_t>(d) * bpm;
      and_v &= static_cast<uint8_t>(m[i - s] & m[i + s]);
      or_v |= static_cast<uint8_t>(m[i - s] | m[i + s]);
    }
    a[i] = and_v;
    o[i] = or_v;
  }
  for (size_t i = row_bytes - reach; i < row_bytes; ++i) clipped(i);
}

using RowWindow = void (*)(const uint8_t*, size_t, size_t, uint8_t*, uint8_t*);
RowWindow row_window_for(int r) {
  switch (r) {
    case 1: return row_window<1>;
    case 2: return row_window<2>;
    case 3: return row_window<3>;
    case 4: return row_window<4>;
    case 5: return row_window<5>;
    case 6: return row_window<6>;
    case 7: return row_window<7>;
    default: return row_window<8>;
  }
}

}  // namespace

uint32_t hard_field_bits(const VisibilityLayout& layout) {
  uint32_t bits = 0;
  for (uint32_t i = 0; i < layout.light_count; ++i) {
    if (!layout.is_soft(i)) bits |= 1u << layout.offset[i];
  }
  return bits;
}

VisibilityBuffer edge_band_marks(const VisibilityBuffer& buffer, std::span<const uint8_t> row_valid, uint32_t band,
                                 uint32_t bits) {
  if (band > kMaxEdgeBand) throw std::invalid_argument("edge band above " + std::to_string(kMaxEdgeBand) + " pixels");
  if (!row_valid.empty() && row_valid.size() != buffer.height) {
    throw std::invalid_argument("edge band: row validity of another length than the buffer's rows");
  }
  VisibilityBuffer marks;  // zero where nothing is marked
  marks.width = buffer.width;
  marks.height = buffer.height;
  marks.light_count = buffer.light_count;
  marks.mask_bits = buffer.mask_bits;
  marks.data.assign(buffer.data.size(), uint8_t{0});
  if (band == 0 || bits == 0) return marks;
  const size_t bpm = buffer.bytes_per_mask();
  const size_t row_bytes = size_t{buffer.width} * bpm;
  const auto h = static_cast<int>(buffer.height), r = static_cast<int>(band);
  const auto arrived = [&](int y) { return row_valid.empty() || row_valid[static_cast<size_t>(y)] != 0; };
  // The row pass's results of the last 2 band + 1 rows, a ring (row t in slot t mod k): cache-sized, no
  // full-buffer scratch.
  const auto k = static_cast<size_t>(2 * r + 1);
  std::vector<uint8_t> ring_and(k * row_bytes), ring_or(k * row_bytes), col_and(row_bytes), col_or(row_bytes);
  static_assert(kMaxEdgeBand == 8, "row_window_for covers bands 1 to 8");
  const RowWindow row_pass = row_window_for(r);
  for (int y = 0; y < h + r; ++y) {
    if (y < h && arrived(y)) {
      row_pass(buffer.data.data() + static_cast<size_t>(y) * row_bytes, row_bytes, bpm,
               ring_and.data() + static_cast<size_t>(y) % k * row_bytes,
               ring_or.data() + static_cast<size_t>(y) % k * row_bytes);
    }
    const int out = y - r;  // every row within r of it has been through the row pass
    if (out < 0 || !arrived(out)) continue;  // a lost row's marks stay 0
    // Column pass: over the arrived rows within r (the pixel's own among them); marks = (OR ^ AND) & bits.
    std::memset(col_and.data(), 0xFF, row_bytes);
    std::memset(col_or.data(), 0, row_bytes);
    for (int t = std::max(0, out - r); t <= std::min(h - 1, out + r); ++t) {
      if (!arrived(t)) continue;
      const uint8_t* __restrict a = ring_and.data() + static_cast<size_t>(t) % k * row_bytes;
      const uint8_t* __restrict o = ring_or.data() + static_cast<size_t>(t) % k * row_bytes;
      uint8_t* __restrict ca = col_and.data();
      uint8_t* __restrict co = col_or.data();
      for (size_t i = 0; i < row_bytes; ++i) {
        ca[i] &= a[i];
        co[i] |= o[i];
      }
    }
    uint8_t* dst = marks.data.data() + static_cast<size_t>(out) * row_bytes;
    switch (buffer.mask_bits) {
      case MaskWidth::k8: keep_bits<uint8_t>(col_and.data(), col_or.data(), buffer.width, bits, dst); break;
      case MaskWidth::k16: keep_bits<uint16_t>(col_and.data(), col_or.data(), buffer.width, bits, dst); break;
      case MaskWidth::k32: keep_bits<uint32_t>(col_and.data(), col_or.data(), buffer.width, bits, dst); break;
    }
  }
  return marks;
}

}  // namespace dhr::render
