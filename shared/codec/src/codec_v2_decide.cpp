#include "codec_v2_decide.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

namespace dhr::codec_detail {
namespace {

// `v` in every Mask-wide lane of a 64-bit word.
template <typename Mask>
constexpr uint64_t lanes(uint64_t v) {
  uint64_t out = 0;
  for (size_t i = 0; i < 8 / sizeof(Mask); ++i) out |= v << (8 * sizeof(Mask) * i);
  return out;
}

// Nonzero Mask-wide lanes of x (SWAR: a lane's top bit is set after adding 0x7F.. to its low bits when any of them
// is, or it was set already; the top bits, moved to each lane's bit 0, are summed into the top lane by one multiply).
template <typename Mask>
uint32_t nonzero_lanes(uint64_t x) {
  constexpr uint32_t kBits = 8 * sizeof(Mask);
  constexpr uint64_t kLow = lanes<Mask>(static_cast<Mask>(~Mask{0}) >> 1), kOne = lanes<Mask>(1);
  const uint64_t top = ((((x & kLow) + kLow) | x) >> (kBits - 1)) & kOne;
  return static_cast<uint32_t>((top * kOne) >> (64 - kBits));
}

// OR of each sub-block's differences from the displaced reference row; returns their OR.
template <typename Mask>
uint32_t row_diff(const uint8_t* a, const uint8_t* r, uint32_t w, uint32_t sub_cols, uint32_t* diff) {
  uint32_t block = 0;
  for (uint32_t sc = 0; sc < sub_cols; ++sc) {
    const uint32_t end = std::min(w, (sc + 1) * kSub);
    Mask d = 0;
    for (uint32_t i = sc * kSub; i < end; ++i) d |= at<Mask>(a, i) ^ at<Mask>(r, i);
    diff[sc] |= d;
    block |= d;
  }
  return block;
}

// Pixels of one row whose `bits` differ from the displaced reference row.
template <typename Mask>
uint32_t row_cost(const uint8_t* a, const uint8_t* b, uint32_t w, uint32_t bits) {
  const Mask m = static_cast<Mask>(bits);
  constexpr uint32_t kPerWord = 8 / sizeof(Mask);
  const uint64_t wm = lanes<Mask>(m);
  uint32_t n = 0, i = 0;
  for (; i + kPerWord <= w; i += kPerWord)
    n += nonzero_lanes<Mask>((word_at(a + i * sizeof(Mask)) ^ word_at(b + i * sizeof(Mask))) & wm);
  for (; i < w; ++i) n += ((at<Mask>(a, i) ^ at<Mask>(b, i)) & m) != 0 ? 1u : 0u;
  return n;
}

class Decider {
 public:
  Decider(const VisibilityBuffer& cur, const V2Reference* reference)
      : cur_(cur),
        ref_(reference != nullptr ? reference->buffer : nullptr),
        current_camera_(reference != nullptr ? reference->current_camera : nullptr),
        reference_camera_(reference != nullptr ? reference->reference_camera : nullptr),
        mb_(cur.bytes_per_mask()) {}

  // Memoized: a block row that overflowed a shard is coded again at the start of the next one, and a band that
  // falls back from 32- to 8-row blocks codes its rows again, with the same inputs where the vectors agree.
  BlockPlan operator()(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, Vector previous, Vector above) {
    const Key key{x0, y0, w, h, previous.x, previous.y, above.x, above.y};
    const auto found = memo_.find(key);
    if (found != memo_.end()) return found->second;
    return memo_.emplace(key, decide(x0, y0, w, h, previous, above)).first->second;
  }

 private:
  using Key = std::array<int64_t, 8>;

  BlockPlan decide(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, Vector previous, Vector above) const {
    BlockPlan plan;
    const uint32_t sub_cols = (w + kSub - 1) / kSub, sub_rows = (h + kSub - 1) / kSub;
    std::array<uint32_t, kMaxSubBlocks> all{}, any{}, diff{};
    all.fill(0xFFFFFFFFu);
    with_mask_type(mb_, [&]<typename Mask>() {
      block_all_any<Mask>(cur_.data.data(), cur_.width, x0, y0, w, h, sub_cols, all.data(), any.data());
    });
    uint32_t block_all = 0xFFFFFFFFu, block_any = 0, block_diff = 0;
    for (uint32_t s = 0; s < sub_cols * sub_rows; ++s) {
      block_all &= all[s];
      block_any |= any[s];
    }
    const uint32_t mixed = (block_all ^ block_any) & cur_.light_bits();
    if (ref_ != nullptr && mixed != 0) {
      plan.vector = search(x0, y0, w, h, mixed, {previous, above, Vector{}, hint(x0, y0, w, h)});
      for (uint32_t y = y0; y < y0 + h; ++y) {
        const uint32_t srow = ((y - y0) / kSub) * sub_cols;
        const int64_t ry = int64_t{y} + plan.vector.y, rx = int64_t{x0} + plan.vector.x;
        if (ry >= 0 && ry < ref_->height && rx >= 0 && rx + w <= ref_->width) {
          const uint8_t* a = &cur_.data[(size_t{y} * cur_.width + x0) * mb_];
          const uint8_t* r = &ref_->data[(static_cast<size_t>(ry) * ref_->width + static_cast<size_t>(rx)) * mb_];
          block_diff |= with_mask_type(mb_, [&]<typename Mask>() { return row_diff<Mask>(a, r, w, sub_cols, &diff[srow]); });
          continue;
        }
        for (uint32_t x = x0; x < x0 + w; ++x) {
          const uint32_t d = cur_mask(x, y) ^ ref_mask(int64_t{x} + plan.vector.x, ry);
          diff[srow + (x - x0) / kSub] |= d;
          block_diff |= d;
        }
      }
    }
    for (uint32_t l = 0; l < cur_.light_count; ++l) {
      const uint32_t bit = 1u << l;
      if (!(mixed & bit)) {
        plan.mode[l] = (block_any & bit) ? kUniform1 : kUniform0;
      } else if (ref_ != nullptr && !(block_diff & bit)) {
        plan.mode[l] = kCopy;
      } else {
        plan.mode[l] = kCoded;
        for (uint32_t s = 0; s < sub_cols * sub_rows; ++s) {
          plan.sub[l][s] = !((all[s] ^ any[s]) & bit)     ? ((any[s] & bit) ? kUniform1 : kUniform0)
                           : ref_ != nullptr && !(diff[s] & bit) ? kCopy
                                                                 : kCoded;
        }
      }
    }
    return plan;
  }

  uint32_t cur_mask(uint32_t x, uint32_t y) const {
    return load_mask(&cur_.data[(size_t{y} * cur_.width + x) * mb_], mb_);
  }
  uint32_t ref_mask(int64_t x, int64_t y) const {
    if (x < 0 || y < 0 || x >= ref_->width || y >= ref_->height) return 0;
    return load_mask(&ref_->data[(static_cast<size_t>(y) * ref_->width + static_cast<size_t>(x)) * mb_], mb_);
  }

  // Pixels whose `bits` differ from the reference displaced by v; stops counting past `limit`.
  uint64_t cost(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t bits, Vector v, uint64_t limit) const {
    return with_mask_type(mb_, [&]<typename Mask>() { return cost_at<Mask>(x0, y0, w, h, bits, v, limit); });
  }
  template <typename Mask>
  uint64_t cost_at(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t bits, Vector v, uint64_t limit) const {
    uint64_t n = 0;
    for (uint32_t y = y0; y < y0 + h; ++y) {
      const int64_t ry = int64_t{y} + v.y, rx = int64_t{x0} + v.x;
      if (ry >= 0 && ry < ref_->height && rx >= 0 && rx + w <= ref_->width) {
        const uint8_t* a = &cur_.data[(size_t{y} * cur_.width + x0) * sizeof(Mask)];
        const uint8_t* b = &ref_->data[(static_cast<size_t>(ry) * ref_->width + static_cast<size_t>(rx)) * sizeof(Mask)];
        n += row_cost<Mask>(a, b, w, bits);
        if (n > limit) return n;
        continue;
      }
      for (uint32_t x = x0; x < x0 + w; ++x)
        n += ((cur_mask(x, y) ^ ref_mask(int64_t{x} + v.x, int64_t{y} + v.y)) & bits) != 0 ? 1 : 0;
      if (n > limit) return n;
    }
    return n;
  }

  static Vector clamp(Vector v) {
    return Vector{std::clamp(v.x, -kV2MaxVector, kV2MaxVector), std::clamp(v.y, -kV2MaxVector, kV2MaxVector)};
  }

  // Where the block's centre direction lands in the reference camera (rotation only: a point far away).
  Vector hint(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) const {
    if (current_camera_ == nullptr || reference_camera_ == nullptr) return Vector{};
    const double cx = x0 + 0.5 * w, cy = y0 + 0.5 * h;
    const glm::dvec3 far_point = current_camera_->T_world_eye.position + current_camera_->world_ray(cx, cy) * 1.0e4;
    const Reprojection r = reproject(*reference_camera_, far_point);
    if (r.status == Reprojection::Status::kBehind) return Vector{};
    const double dx = r.pixel.x - cx, dy = r.pixel.y - cy;
    if (!std::isfinite(dx) || !std::isfinite(dy) || std::fabs(dx) > 1e6 || std::fabs(dy) > 1e6) return Vector{};
    return clamp(Vector{static_cast<int32_t>(std::lround(dx)), static_cast<int32_t>(std::lround(dy))});
  }

  // The candidate with the fewest mismatching pixels, then a descent over the 8 neighbours. A vector already
  // measured is not measured again (the candidates often coincide, and a step's neighbours overlap the last step's):
  // its count was no lower than the best then, and the best only falls, so the result is the same.
  Vector search(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t bits,
                std::initializer_list<Vector> candidates) const {
    Vector best;
    uint64_t best_cost = std::numeric_limits<uint64_t>::max();
    std::array<Vector, 4 + 3 * 8> seen;
    size_t seen_count = 0;
    auto first_time = [&](Vector v) {
      if (std::find(seen.begin(), seen.begin() + seen_count, v) != seen.begin() + seen_count) return false;
      if (seen_count < seen.size()) seen[seen_count++] = v;
      return true;
    };
    for (const Vector c : candidates) {
      const Vector v = clamp(c);
      if (!first_time(v)) continue;
      const uint64_t n = cost(x0, y0, w, h, bits, v, best_cost);
      if (n < best_cost) {
        best_cost = n;
        best = v;
      }
      if (best_cost == 0) return best;
    }
    for (int step = 0; step < 3 && best_cost > 0; ++step) {
      const Vector centre = best;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx == 0 && dy == 0) continue;
          const Vector v = clamp(Vector{centre.x + dx, centre.y + dy});
          if (!first_time(v)) continue;
          const uint64_t n = cost(x0, y0, w, h, bits, v, best_cost);
          if (n < best_cost) {
            best_cost = n;
            best = v;
          }
        }
      }
      if (best == centre) break;
    }
    return best;
  }

  const VisibilityBuffer& cur_;
  const VisibilityBuffer* ref_;
  const Camera* current_camera_;
  const Camera* reference_camera_;
  uint32_t mb_;
  std::map<Key, BlockPlan> memo_;
};

}  // namespace

BlockDecider make_block_decider(const VisibilityBuffer& buffer, const V2Reference* reference) {
  return Decider(buffer, reference);
}

}  // namespace dhr::codec_detail
