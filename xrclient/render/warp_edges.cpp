#include "render/warp_edges.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace dhr::render {
namespace {

static_assert(std::endian::native == std::endian::little, "the masks are copied as little-endian integers");

// One mask width: the masks as T (the buffer's little-endian bytes, copied), two passes of plain loops over
// whole rows that the compiler vectorizes.
template <typename T>
void marks_of_width(const VisibilityBuffer& buffer, std::span<const uint8_t> row_valid, int r, uint32_t bits,
                    VisibilityBuffer& out) {
  const auto w = static_cast<size_t>(buffer.width);
  const auto h = static_cast<int>(buffer.height);
  const auto arrived = [&](int y) { return row_valid.empty() || row_valid[static_cast<size_t>(y)] != 0; };
  const T keep = static_cast<T>(bits);
  std::vector<T> masks(buffer.pixel_count()), row_and(buffer.pixel_count()), row_or(buffer.pixel_count());
  std::memcpy(masks.data(), buffer.data.data(), buffer.size_bytes());
  // Row pass: per arrived row, the AND and OR of the pixels within r in that row.
  for (int y = 0; y < h; ++y) {
    if (!arrived(y)) continue;
    const T* m = masks.data() + static_cast<size_t>(y) * w;
    T* a = row_and.data() + static_cast<size_t>(y) * w;
    T* o = row_or.data() + static_cast<size_t>(y) * w;
    for (size_t x = 0; x < w; ++x) a[x] = o[x] = static_cast<T>(m[x] & keep);
    for (int d = 1; d <= r; ++d) {
      const auto s = static_cast<size_t>(d);
      if (s >= w) break;
      for (size_t x = 0; x + s < w; ++x) {  // the neighbour d to the right, then d to the left
        a[x] = static_cast<T>(a[x] & m[x + s] & keep);
        o[x] = static_cast<T>(o[x] | (m[x + s] & keep));
      }
      for (size_t x = s; x < w; ++x) {
        a[x] = static_cast<T>(a[x] & m[x - s] & keep);
        o[x] = static_cast<T>(o[x] | (m[x - s] & keep));
      }
    }
  }
  // Column pass: over the arrived rows within r (the pixel's own among them); marks = OR ^ AND.
  std::vector<T> col_and(w), col_or(w);
  T* marks = masks.data();  // reused for the result
  for (int y = 0; y < h; ++y) {
    T* dst = marks + static_cast<size_t>(y) * w;
    if (!arrived(y)) {
      std::fill(dst, dst + w, T{0});
      continue;
    }
    std::fill(col_and.begin(), col_and.end(), static_cast<T>(~T{0}));
    std::fill(col_or.begin(), col_or.end(), T{0});
    for (int t = std::max(0, y - r); t <= std::min(h - 1, y + r); ++t) {
      if (!arrived(t)) continue;
      const T* a = row_and.data() + static_cast<size_t>(t) * w;
      const T* o = row_or.data() + static_cast<size_t>(t) * w;
      for (size_t x = 0; x < w; ++x) {
        col_and[x] = static_cast<T>(col_and[x] & a[x]);
        col_or[x] = static_cast<T>(col_or[x] | o[x]);
      }
    }
    for (size_t x = 0; x < w; ++x) dst[x] = static_cast<T>(col_and[x] ^ col_or[x]);
  }
  std::memcpy(out.data.data(), masks.data(), buffer.size_bytes());
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
  VisibilityBuffer marks = buffer;
  if (band == 0 || bits == 0) {
    std::fill(marks.data.begin(), marks.data.end(), uint8_t{0});
    return marks;
  }
  const auto r = static_cast<int>(band);
  switch (buffer.mask_bits) {
    case MaskWidth::k8: marks_of_width<uint8_t>(buffer, row_valid, r, bits, marks); break;
    case MaskWidth::k16: marks_of_width<uint16_t>(buffer, row_valid, r, bits, marks); break;
    case MaskWidth::k32: marks_of_width<uint32_t>(buffer, row_valid, r, bits, marks); break;
  }
  return marks;
}

}  // namespace dhr::render
