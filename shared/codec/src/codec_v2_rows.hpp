// Row loops at a mask's width and a block's 64-bit reads (private to dhr_codec), shared by the band coder
// (codec_v2_band.hpp) and the encoder's decisions (codec_v2_decide.cpp).
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace dhr::codec_detail {

inline constexpr uint32_t kBlockW = 32;
inline constexpr uint32_t kSub = 8;
inline constexpr uint32_t kMaxSubBlocks = (kBlockW / kSub) * (32 / kSub);

// Row loops at the mask's width: `at` loads mask i of a row of Mask-wide masks (8, 16 or 32 bits, little-endian
// as the buffers are, one load), `put` stores one, and with_mask_type calls f.template operator()<Mask>() for a
// buffer's width.
template <typename Mask>
Mask at(const uint8_t* row, size_t i) {
  Mask m;
  std::memcpy(&m, row + i * sizeof(Mask), sizeof m);
  return m;
}
template <typename Mask>
void put(uint8_t* row, size_t i, Mask m) {
  std::memcpy(row + i * sizeof(Mask), &m, sizeof m);
}
template <typename F>
decltype(auto) with_mask_type(uint32_t mask_bytes, F&& f) {
  if (mask_bytes == 1) return f.template operator()<uint8_t>();
  if (mask_bytes == 2) return f.template operator()<uint16_t>();
  return f.template operator()<uint32_t>();
}

// Eight bytes of a row, little-endian as the buffers are (one load).
inline uint64_t word_at(const uint8_t* p) {
  uint64_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// The lanes of a 64-bit word of Mask-wide masks folded into one mask by AND (or OR).
template <typename Mask>
Mask fold_and(uint64_t v) {
  for (uint32_t shift = 32; shift >= 8 * sizeof(Mask); shift /= 2) v &= v >> shift;
  return static_cast<Mask>(v);
}
template <typename Mask>
Mask fold_or(uint64_t v) {
  for (uint32_t shift = 32; shift >= 8 * sizeof(Mask); shift /= 2) v |= v >> shift;
  return static_cast<Mask>(v);
}

// AND and OR of each 8x8 sub-block's masks of the block at (x0, y0), w x h (w <= kBlockW), in a buffer of `width`
// masks per row (the bits above the mask's width set in `all`). Row by row, each sub-block column's 8 masks go 64
// bits at a time into that column's accumulators, folded once per sub-block.
template <typename Mask>
void block_all_any(const uint8_t* data, size_t width, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h,
                   uint32_t sub_cols, uint32_t* all, uint32_t* any) {
  constexpr uint32_t kAbove = sizeof(Mask) == 4 ? 0u : ~uint32_t{0} << (8 * sizeof(Mask));
  constexpr uint32_t kCols = kBlockW / kSub;
  const uint32_t full_cols = w / kSub;  // sub-block columns of 8 masks; a narrower one at the buffer's right edge
  for (uint32_t sy = 0; sy * kSub < h; ++sy) {
    const uint32_t rows = std::min(kSub, h - sy * kSub);
    uint64_t wa[kCols], wo[kCols];
    Mask a = static_cast<Mask>(~Mask{0}), o = 0;  // the narrow column's
    for (uint32_t c = 0; c < kCols; ++c) {
      wa[c] = ~uint64_t{0};
      wo[c] = 0;
    }
    for (uint32_t r = 0; r < rows; ++r) {
      const uint8_t* row = data + (size_t{y0 + sy * kSub + r} * width + x0) * sizeof(Mask);
      if (full_cols == kCols) {
        for (uint32_t c = 0; c < kCols; ++c)
          for (uint32_t k = 0; k < sizeof(Mask); ++k) {
            const uint64_t v = word_at(row + (c * sizeof(Mask) + k) * 8);
            wa[c] &= v;
            wo[c] |= v;
          }
        continue;
      }
      for (uint32_t c = 0; c < full_cols; ++c)
        for (uint32_t k = 0; k < sizeof(Mask); ++k) {
          const uint64_t v = word_at(row + (c * sizeof(Mask) + k) * 8);
          wa[c] &= v;
          wo[c] |= v;
        }
      for (uint32_t i = full_cols * kSub; i < w; ++i) {
        const Mask m = at<Mask>(row, i);
        a &= m;
        o |= m;
      }
    }
    for (uint32_t c = 0; c < sub_cols; ++c) {
      const bool narrow = c == full_cols;
      all[sy * sub_cols + c] = kAbove | (narrow ? a : fold_and<Mask>(wa[c]));
      any[sy * sub_cols + c] = narrow ? o : fold_or<Mask>(wo[c]);
    }
  }
}

}  // namespace dhr::codec_detail
