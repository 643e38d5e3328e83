// The v2 band coder (private to dhr_codec): one function template codes a shard's rows with either the
// BitEncoder or the BitDecoder (range_coder.hpp), so the two sides cannot drift apart. The encoder supplies
// its decisions (modes, vectors) per block; the decoder reads them from the stream and writes the pixels.
#pragma once
#include "codec_v2_models.hpp"
#include "codec_v2_rows.hpp"
#include "range_coder.hpp"
#include "visibility/visibility.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <functional>
#include <vector>

namespace dhr::codec_detail {

enum BlockMode : uint8_t { kUniform0 = 0, kUniform1 = 1, kCopy = 2, kCoded = 3 };

struct BandGeometry {
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t y0 = 0;  // first row of the shard
  uint32_t y1 = 0;  // one past its last row
  uint32_t block_rows = 32;
  uint32_t light_count = 0;
  uint32_t mask_bytes = 1;
};

struct Vector {
  int32_t x = 0;
  int32_t y = 0;
  bool operator==(const Vector&) const = default;
};

// One block's decisions: per light a mode, per light and 8x8 sub-block a mode (coded blocks), the vector.
struct BlockPlan {
  std::array<uint8_t, kMaxLights> mode{};
  std::array<std::array<uint8_t, kMaxSubBlocks>, kMaxLights> sub{};
  Vector vector;
};


// Counters the band coder keeps (the encoder reports them).
struct BandCounts {
  size_t blocks = 0, uniform = 0, copied = 0, coded = 0, pixels_coded = 0;
};

// The encoder's decision for the block at (x0, y0) of size w x h, given the previous block's vector and the
// vector of the block above (both zero at the shard's start).
using BlockDecider = std::function<BlockPlan(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, Vector previous,
                                             Vector above)>;

template <class Io>
class BandCoder {
 public:
  // `cur`: the whole buffer's mask bytes (the encoder only reads it); `ref`: the reference's, or null (intra).
  BandCoder(Io& io, const BandGeometry& g, uint8_t* cur, const uint8_t* ref, Models& models)
      : io_(io), g_(g), cur_(cur), ref_(ref), m_(models) {}

  // Codes every block of the band; false when the decoder met an impossible value (hostile input) or when
  // `after_row` (called with the next block row's first row) asked to stop.
  bool run(const BlockDecider* decide, BandCounts& counts, const std::function<bool(uint32_t)>& after_row = {}) {
    std::vector<Vector> above((g_.width + kBlockW - 1) / kBlockW);
    for (uint32_t by = g_.y0; by < g_.y1; by += g_.block_rows) {
      Vector previous;
      const uint32_t h = std::min(g_.block_rows, g_.y1 - by);
      for (uint32_t bx = 0, col = 0; bx < g_.width; bx += kBlockW, ++col) {
        const uint32_t w = std::min(kBlockW, g_.width - bx);
        BlockPlan plan;
        if constexpr (!Io::kDecoding) plan = (*decide)(bx, by, w, h, previous, above[col]);
        if (!code_block(plan, bx, by, w, h, previous, counts)) return false;
        if (uses_reference(plan)) previous = plan.vector;
        above[col] = previous;
      }
      if (after_row && !after_row(by + h)) return false;
    }
    return true;
  }

 private:
  bool uses_reference(const BlockPlan& plan) const {
    if (ref_ == nullptr) return false;
    for (uint32_t l = 0; l < g_.light_count; ++l)
      if (plan.mode[l] == kCopy || plan.mode[l] == kCoded) return true;
    return false;
  }

  // Mode of one block or sub-block: coded?; (inter) copy?; uniform value.
  uint8_t code_mode(uint8_t mode, int level, uint8_t rs, bool left_coded, uint8_t& last_value) {
    const bool inter = ref_ != nullptr;
    if (io_.bit(m_.coded[level][inter][rs][left_coded ? 1 : 0], mode == kCoded)) return kCoded;
    if (inter && io_.bit(m_.copy[level][rs], mode == kCopy)) return kCopy;
    const bool one = io_.bit(m_.value[level][inter][rs][last_value], mode == kUniform1);
    last_value = one ? 1 : 0;
    return one ? kUniform1 : kUniform0;
  }

  bool code_component(int32_t& value, int axis) {
    const bool nonzero = io_.bit(m_.vec_zero[axis], value != 0);
    if (!nonzero) {
      value = 0;
      return true;
    }
    const bool negative = io_.bit(m_.vec_sign[axis], value < 0);
    const uint32_t magnitude = static_cast<uint32_t>(value < 0 ? -value : value);
    uint32_t got = 1;
    // Unary up to kVectorMagnitudeContexts, then 9 bits of escape (a delta spans at most 2 * 255).
    while (got < kVectorMagnitudeContexts + 1) {
      if (!io_.bit(m_.vec_magnitude[axis][got - 1], magnitude > got)) break;
      ++got;
    }
    if (got == kVectorMagnitudeContexts + 1) {
      const uint32_t rest = magnitude - got;
      uint32_t decoded = 0;
      for (int b = 8; b >= 0; --b)
        decoded |= (io_.bit(m_.vec_escape[b], ((rest >> b) & 1u) != 0) ? 1u : 0u) << b;
      got += decoded;
    }
    value = negative ? -static_cast<int32_t>(got) : static_cast<int32_t>(got);
    return true;
  }

  bool code_vector(Vector& v, Vector predictor) {
    Vector delta{v.x - predictor.x, v.y - predictor.y};
    if (!code_component(delta.x, 0) || !code_component(delta.y, 1)) return false;
    v = Vector{predictor.x + delta.x, predictor.y + delta.y};
    return v.x >= -255 && v.x <= 255 && v.y >= -255 && v.y <= 255;
  }

  // ORs into [x0, x0+w) x [y0, y0+h): `one` bits everywhere, `copy` bits from the reference displaced by v. With
  // `assign`, writes those bits instead (every other bit 0): a block's first fill, in place of clearing it.
  void fill(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t one, uint32_t copy, Vector v,
            bool assign = false) {
    if ((one | copy) == 0 && !assign) return;
    with_mask_type(g_.mask_bytes, [&]<typename Mask>() {
      if (assign)
        fill_rows<Mask, true>(x0, y0, w, h, one, copy, v);
      else
        fill_rows<Mask, false>(x0, y0, w, h, one, copy, v);
    });
  }
  template <typename Mask, bool kAssign>
  void fill_rows(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t one, uint32_t copy, Vector v) {
    const Mask o = static_cast<Mask>(one), c = static_cast<Mask>(copy);
    auto old = [](const uint8_t* dst, uint32_t i) { return kAssign ? Mask{0} : at<Mask>(dst, i); };
    for (uint32_t y = y0; y < y0 + h; ++y) {
      uint8_t* dst = cur_ + (size_t{y} * g_.width + x0) * sizeof(Mask);
      const int64_t ry = int64_t{y} + v.y, rx0 = int64_t{x0} + v.x;
      if (kAssign && copy == 0 && one == 0) {
        std::memset(dst, 0, size_t{w} * sizeof(Mask));
      } else if (copy == 0) {
        for (uint32_t i = 0; i < w; ++i) put<Mask>(dst, i, static_cast<Mask>(old(dst, i) | o));
      } else if (ry >= 0 && ry < g_.height && rx0 >= 0 && rx0 + w <= g_.width) {  // the row's source is inside
        const uint8_t* src = ref_ + (static_cast<size_t>(ry) * g_.width + static_cast<size_t>(rx0)) * sizeof(Mask);
        for (uint32_t i = 0; i < w; ++i)
          put<Mask>(dst, i, static_cast<Mask>(old(dst, i) | o | (at<Mask>(src, i) & c)));
      } else {  // partly outside the reference: those pixels copy 0
        for (uint32_t i = 0; i < w; ++i) {
          const Mask r = static_cast<Mask>(load_ref(rx0 + i, ry) & copy);
          put<Mask>(dst, i, static_cast<Mask>(old(dst, i) | o | r));
        }
      }
    }
  }
  uint32_t load_ref(int64_t x, int64_t y) const {
    if (x < 0 || y < 0 || x >= g_.width || y >= g_.height) return 0;
    return load_mask(ref_ + (static_cast<size_t>(y) * g_.width + static_cast<size_t>(x)) * g_.mask_bytes, g_.mask_bytes);
  }

  // The OR and the AND of the reference's masks over [x0, x0+w) x [y0, y0+h) displaced by v, where that region
  // leaves the reference: pixels outside it are 0, as a copy gives them. 8 bytes at a time where they fit.
  void or_and(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, Vector v, uint32_t& any, uint32_t& all) const {
    with_mask_type(g_.mask_bytes, [&]<typename Mask>() {
      Mask o = 0, a = static_cast<Mask>(~Mask{0});
      uint64_t o64 = 0, a64 = ~uint64_t{0};
      const int64_t rx0 = int64_t{x0} + v.x;
      const int64_t xb = std::max<int64_t>(rx0, 0), xe = std::min<int64_t>(rx0 + w, g_.width);
      if (xb > rx0 || xe < rx0 + w) a = 0;
      const size_t bytes = xe > xb ? static_cast<size_t>(xe - xb) * sizeof(Mask) : 0;
      for (uint32_t y = y0; y < y0 + h; ++y) {
        const int64_t ry = int64_t{y} + v.y;
        if (ry < 0 || ry >= g_.height || bytes == 0) {
          a = 0;
          continue;
        }
        const uint8_t* src = ref_ + (static_cast<size_t>(ry) * g_.width + static_cast<size_t>(xb)) * sizeof(Mask);
        size_t i = 0;
        for (; i + 8 <= bytes; i += 8) {
          o64 |= word_at(src + i);
          a64 &= word_at(src + i);
        }
        for (; i < bytes; i += sizeof(Mask)) {
          o = static_cast<Mask>(o | at<Mask>(src + i, 0));
          a = static_cast<Mask>(a & at<Mask>(src + i, 0));
        }
      }
      any = static_cast<Mask>(o | fold_or<Mask>(o64));
      all = static_cast<Mask>(a & fold_and<Mask>(a64));
    });
  }

  // or_and of each sub-block of the block at (bx, by), w x h, displaced by v in the reference: block_all_any
  // (64-bit reads, one pass) where the displaced block lies inside the reference, else or_and per sub-block.
  void sub_block_or_and(uint32_t bx, uint32_t by, uint32_t w, uint32_t h, Vector v, uint32_t subs,
                        std::array<uint32_t, kMaxSubBlocks>& any, std::array<uint32_t, kMaxSubBlocks>& all) const {
    const int64_t rx0 = int64_t{bx} + v.x, ry0 = int64_t{by} + v.y;
    const uint32_t sub_cols = (w + kSub - 1) / kSub;
    if (rx0 >= 0 && ry0 >= 0 && rx0 + w <= g_.width && ry0 + h <= g_.height) {
      with_mask_type(g_.mask_bytes, [&]<typename Mask>() {
        block_all_any<Mask>(ref_, g_.width, static_cast<uint32_t>(rx0), static_cast<uint32_t>(ry0), w, h, sub_cols,
                            all.data(), any.data());
      });
      return;
    }
    for (uint32_t s = 0; s < subs; ++s) {
      const uint32_t sx = (s % sub_cols) * kSub, sy = (s / sub_cols) * kSub;
      or_and(bx + sx, by + sy, std::min(kSub, w - sx), std::min(kSub, h - sy), v, any[s], all[s]);
    }
  }

  // out[i] = bit `light` of the mask at row column x_begin + i, for i < count.
  void extract_bits(const uint8_t* row, int64_t x_begin, int64_t count, uint32_t light, uint8_t* out) const {
    with_mask_type(g_.mask_bytes, [&]<typename Mask>() {
      const uint8_t* in = row + static_cast<size_t>(x_begin) * sizeof(Mask);
      for (int64_t i = 0; i < count; ++i)
        out[i] = static_cast<uint8_t>((at<Mask>(in, static_cast<size_t>(i)) >> light) & 1u);
    });
  }

  // The coded pixels of light l in a block, raster order, with the contexts read from local copies of the
  // light's plane (2 rows above, 2 columns each side; unknown neighbours 0) and of the displaced reference.
  void code_pixels(const BlockPlan& plan, uint32_t l, uint32_t bx, uint32_t by, uint32_t w, uint32_t h,
                   uint32_t sub_cols, BandCounts& counts) {
    const uint32_t lw = w + 4;  // local plane: columns bx-2 .. bx+w+1, rows by-2 .. by+h-1
    plane_.assign(size_t{lw} * (h + 2), 0);
    const uint32_t bx1 = bx + w;
    const uint32_t mb = g_.mask_bytes;
    const bool inter = ref_ != nullptr;
    if (inter) ref_plane_.assign(size_t{w + 2} * (h + 2), 0);  // rows by-1 .. by+h, columns bx-1 .. bx+w, displaced
    // Only the neighbourhoods of coded sub-blocks are read: each run of coded sub-blocks in a sub-block row is
    // copied from the buffers with its neighbourhood (overlaps get the same values twice); the rest of the local
    // planes stays 0, unread.
    const uint32_t sub_rows = (h + kSub - 1) / kSub;
    for (uint32_t sr = 0; sr < sub_rows; ++sr) {
      const uint8_t* modes = &plan.sub[l][sr * sub_cols];
      for (uint32_t sc = 0; sc < sub_cols; ++sc) {
        if (modes[sc] != kCoded) continue;
        uint32_t sc_end = sc + 1;
        while (sc_end < sub_cols && modes[sc_end] == kCoded) ++sc_end;
        const uint32_t si = sc * kSub, sj = sr * kSub;
        const uint32_t sw = std::min(sc_end * kSub, w) - si, sh = std::min(kSub, h - sj);
        sc = sc_end;
        // This light's plane: local rows sj .. sj+sh+1 (two above the run's first), columns si .. si+sw+3.
        for (uint32_t r = sj; r < sj + sh + 2; ++r) {
          const int64_t y = int64_t{by} + r - 2;
          if (y < g_.y0 || y >= g_.y1) continue;  // other shards' rows: unknown, 0
          // Known columns: inside the image, and left of the block's right edge in the current block row.
          const int64_t x_begin = std::max<int64_t>(int64_t{bx} + si - 2, 0);
          const int64_t x_end = std::min<int64_t>(
              {int64_t{bx} + si + sw + 2, y >= by ? int64_t{bx1} : int64_t{bx1} + 2, int64_t{g_.width}});
          const uint8_t* row = cur_ + static_cast<size_t>(y) * g_.width * mb;
          if (x_begin < x_end)  // local column of image column x: x - bx + 2
            extract_bits(row, x_begin, x_end - x_begin, l,
                         &plane_[size_t{r} * lw + static_cast<size_t>(x_begin - bx + 2)]);
        }
        if (!inter) continue;
        // The reference: local rows sj .. sj+sh+1, columns si .. si+sw+1.
        for (uint32_t r = sj; r < sj + sh + 2; ++r) {
          const int64_t y = int64_t{by} + r - 1 + plan.vector.y;
          if (y < 0 || y >= g_.height) continue;  // outside the reference: 0
          const int64_t x0 = int64_t{bx} - 1 + plan.vector.x;  // reference column of local column 0
          const int64_t x_begin = std::max<int64_t>(x0 + si, 0), x_end = std::min<int64_t>(x0 + si + sw + 2, g_.width);
          if (x_begin >= x_end) continue;
          extract_bits(ref_ + static_cast<size_t>(y) * g_.width * mb, x_begin, x_end - x_begin, l,
                       &ref_plane_[size_t{r} * (w + 2) + static_cast<size_t>(x_begin - x0)]);
        }
      }
    }
    with_mask_type(mb, [&]<typename Mask>() {
      code_plane<Mask>(plan, l, bx, by, w, h, sub_cols, counts);
    });
  }

  // The pixel loop of code_pixels at the mask's width: each row's runs of coded sub-blocks, the context from the
  // local planes, the bit coded (the encoder's plane holds the truth at the pixel), and (decoder) written.
  template <typename Mask>
  void code_plane(const BlockPlan& plan, uint32_t l, uint32_t bx, uint32_t by, uint32_t w, uint32_t h,
                  uint32_t sub_cols, BandCounts& counts) {
    const uint32_t lw = w + 4;
    const bool inter = ref_ != nullptr;
    const ptrdiff_t stride = w + 2;
    size_t coded = 0;
    for (uint32_t j = 0; j < h; ++j) {
      const uint8_t* row_modes = &plan.sub[l][(j / kSub) * sub_cols];
      uint8_t* p0 = &plane_[size_t{j + 2} * lw + 2];  // this row, at column bx
      const uint8_t* p1 = p0 - lw;                      // row above
      const uint8_t* p2 = p1 - lw;                      // two rows above
      uint8_t* cur_row = cur_ + (size_t{by + j} * g_.width + bx) * sizeof(Mask);
      for (uint32_t sc = 0; sc < sub_cols; ++sc) {
        if (row_modes[sc] != kCoded) continue;
        const uint32_t i_end = std::min(w, (sc + 1) * kSub);
        for (uint32_t i = sc * kSub; i < i_end; ++i) {
          const ptrdiff_t k = i;  // signed: the taps reach two columns to the left
          Probability* prob;
          if (inter) {
            // 4 neighbours (left, and the three above) and 5 reference bits around the displaced position. More
            // neighbours, or the previous light's bit as intra has, split the statistics over more contexts than a
            // shard's models learn: area room, 992x558, 30 frames: 6.632 Mbit/s with intra's 9, 6.532 without the
            // previous light's bit, 6.420 with these 4 neighbours (5: 6.466; 2: 6.591).
            const uint8_t* q = &ref_plane_[size_t{j + 1} * (w + 2) + i + 1];
            const uint32_t c = (uint32_t{p0[k - 1]} << 8) | (uint32_t{p1[k - 1]} << 7) | (uint32_t{p1[k]} << 6) |
                               (uint32_t{p1[k + 1]} << 5) | (uint32_t{q[0]} << 4) | (uint32_t{q[-1]} << 3) |
                               (uint32_t{q[1]} << 2) | (uint32_t{q[-stride]} << 1) | uint32_t{q[stride]};
            prob = &m_.inter[c];
          } else {
            // 8 neighbours: two to the left, five above, one two rows above (the two beside that one were dropped:
            // with models that restart per shard, fewer contexts learn sooner; 1-2 % fewer bytes,
            // docs/performance.md), and the previous light's bit at this pixel (decoded: lights go in order).
            uint32_t c = (uint32_t{p0[k - 1]} << 7) | (uint32_t{p0[k - 2]} << 6) | (uint32_t{p1[k - 2]} << 5) |
                         (uint32_t{p1[k - 1]} << 4) | (uint32_t{p1[k]} << 3) | (uint32_t{p1[k + 1]} << 2) |
                         (uint32_t{p1[k + 2]} << 1) | uint32_t{p2[k]};
            c = (c << 1) | (l > 0 ? (static_cast<uint32_t>(at<Mask>(cur_row, i)) >> (l - 1)) & 1u : 0u);
            prob = &m_.intra[c];
          }
          // The encoder's plane holds the truth at the pixel; the decoder's value is its own.
          const bool bit = io_.bit(*prob, p0[i] != 0);
          if constexpr (Io::kDecoding) {
            p0[i] = bit ? 1 : 0;
            if (bit) put<Mask>(cur_row, i, static_cast<Mask>(at<Mask>(cur_row, i) | (Mask{1} << l)));
          }
          ++coded;
        }
      }
    }
    counts.pixels_coded += coded;
  }

  bool code_block(BlockPlan& plan, uint32_t bx, uint32_t by, uint32_t w, uint32_t h, Vector previous,
                  BandCounts& counts) {
    // 1. A mode per light; 2. the vector; 3. sub-block modes of coded lights; 4. (decoder) everything that is
    // not coded pixel by pixel; 5. the coded pixels, light by light.
    uint8_t last_value = 0;
    bool left_coded = false;
    // The mode contexts' region states (ref_state), per 8x8 sub-block and for the block: inter, the reference under
    // them at the vector's predictor, and under the sub-blocks again at the block's vector where it differs and a
    // light is coded; intra, the 8 rows above the block and its top sub-blocks where those rows are in the shard (a
    // block row's modes come before its pixels).
    const uint32_t sub_cols = (w + kSub - 1) / kSub, sub_rows = (h + kSub - 1) / kSub, subs = sub_cols * sub_rows;
    const bool inter = ref_ != nullptr, above = !inter && by >= g_.y0 + kSub;
    const uint32_t sub_states = inter ? subs : above ? sub_cols : 0;
    std::array<uint32_t, kMaxSubBlocks> sub_any{}, sub_all{};
    auto region_states = [&](Vector v) {
      if (inter) {
        sub_block_or_and(bx, by, w, h, v, subs, sub_any, sub_all);
      } else if (above) {  // one row of sub-blocks: the 8 rows above, inside the shard
        with_mask_type(g_.mask_bytes, [&]<typename Mask>() {
          block_all_any<Mask>(cur_, g_.width, bx, by - kSub, w, kSub, sub_cols, sub_all.data(), sub_any.data());
        });
      }
    };
    region_states(previous);
    uint32_t any = 0, all = ~0u;
    for (uint32_t s = 0; s < sub_states; ++s) {
      any |= sub_any[s];
      all &= sub_all[s];
    }
    for (uint32_t l = 0; l < g_.light_count; ++l) {
      plan.mode[l] = code_mode(plan.mode[l], 0, sub_states > 0 ? ref_state(any, all, l) : kRefNone, left_coded,
                               last_value);
      left_coded = plan.mode[l] == kCoded;
    }
    if (uses_reference(plan) && !code_vector(plan.vector, previous)) return false;
    const bool any_coded = std::any_of(plan.mode.begin(), plan.mode.begin() + g_.light_count,
                                       [](uint8_t m) { return m == kCoded; });
    if (any_coded && uses_reference(plan) && !(plan.vector == previous)) region_states(plan.vector);
    uint32_t one = 0, copy = 0;
    std::array<uint32_t, kMaxSubBlocks> sub_one{}, sub_copy{};
    for (uint32_t l = 0; l < g_.light_count; ++l) {
      ++counts.blocks;
      if (plan.mode[l] != kCoded) {
        ++(plan.mode[l] == kCopy ? counts.copied : counts.uniform);
        one |= plan.mode[l] == kUniform1 ? 1u << l : 0u;
        copy |= plan.mode[l] == kCopy ? 1u << l : 0u;
        continue;
      }
      ++counts.coded;
      uint8_t sub_value = 0;
      for (uint32_t s = 0; s < subs; ++s) {
        const bool left = s % sub_cols > 0 && plan.sub[l][s - 1] == kCoded;
        plan.sub[l][s] = code_mode(plan.sub[l][s], 1, s < sub_states ? ref_state(sub_any[s], sub_all[s], l) : kRefNone,
                                   left, sub_value);
        sub_one[s] |= plan.sub[l][s] == kUniform1 ? 1u << l : 0u;
        sub_copy[s] |= plan.sub[l][s] == kCopy ? 1u << l : 0u;
      }
    }
    if constexpr (Io::kDecoding) {
      fill(bx, by, w, h, one, copy, plan.vector, true);  // the block's every pixel: nothing of an earlier frame stays
      for (uint32_t s = 0; s < subs; ++s) {
        const uint32_t sx = bx + (s % sub_cols) * kSub, sy = by + (s / sub_cols) * kSub;
        fill(sx, sy, std::min(kSub, bx + w - sx), std::min(kSub, by + h - sy), sub_one[s], sub_copy[s], plan.vector);
      }
    }
    for (uint32_t l = 0; l < g_.light_count; ++l) {
      if (plan.mode[l] == kCoded) code_pixels(plan, l, bx, by, w, h, sub_cols, counts);
    }
    return true;
  }

  Io& io_;
  const BandGeometry& g_;
  uint8_t* cur_;
  const uint8_t* ref_;
  Models& m_;
  std::vector<uint8_t> plane_;      // scratch of code_pixels
  std::vector<uint8_t> ref_plane_;
};

}  // namespace dhr::codec_detail
