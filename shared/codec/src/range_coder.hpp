// Adaptive binary range coder (private to dhr_codec): 15-bit probabilities, each adapted after every bit by a shift
// that grows with the bits its context has seen (1 + n / 3, at most 4: a new context learns at once, an old one
// averages over about 16 bits), a 32-bit range renormalized bytewise, carries propagated through a pending-byte
// counter. The coding scheme is the classic one of LZMA's range coder (whose 11-bit probabilities adapt by a fixed
// shift of 5); this is an independent implementation. The models restart with every shard, and a shard visits
// hundreds of its pixel contexts (2^9 intra, 2^9 inter: codec_v2_models.hpp) a few times each: learning fast is what
// pays. Against LZMA's fixed rule this codes the same frames in 31-34 % fewer bytes (docs/performance.md). Integer arithmetic only, so encoder and
// decoder agree bit for bit on every machine.
//
// BitEncoder and BitDecoder share one interface, `bool bit(Probability& p, bool value)`: the encoder codes
// `value` and returns it, the decoder ignores it and returns the decoded bit. Code written once against that
// interface therefore encodes and decodes symmetrically.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace dhr::codec_detail {

inline constexpr uint32_t kProbabilityBits = 15;
inline constexpr uint32_t kProbabilityOne = 1u << kProbabilityBits;
inline constexpr uint16_t kProbabilityHalf = kProbabilityOne / 2;
inline constexpr uint8_t kAdaptShiftMax = 4;
inline constexpr uint8_t kAdaptBitsPerStep = 3;  // the shift grows by one every this many bits seen
inline constexpr uint32_t kTopValue = 1u << 24;

// Probability that the next bit is 0, in units of 1/32768 (never 0 nor 1: the shifts leave a remainder), and
// the adaptation shift for the next bit.
struct Probability {
  uint16_t p0 = kProbabilityHalf;
  uint8_t seen = 0;  // bits coded with it, saturating once the shift is at its maximum

  // The shift for this bit (1 + seen / kAdaptBitsPerStep, at most kAdaptShiftMax), and one more bit seen: `seen`
  // stops where the shift reaches its maximum. A table and a select instead of a division and a branch: the same
  // shifts, 6 % less decode time on the area room (docs/performance.md, "Faster coding loops").
  static constexpr uint8_t kSeenMax = (kAdaptShiftMax - 1) * kAdaptBitsPerStep;
  static constexpr std::array<uint8_t, kSeenMax + 1> kShift = [] {
    std::array<uint8_t, kSeenMax + 1> t{};
    for (uint32_t n = 0; n <= kSeenMax; ++n) t[n] = static_cast<uint8_t>(1 + n / kAdaptBitsPerStep);
    return t;
  }();
  uint32_t next_shift() {
    const uint32_t shift = kShift[seen];
    seen = static_cast<uint8_t>(seen < kSeenMax ? seen + 1 : seen);
    return shift;
  }
  void saw_zero() { p0 = static_cast<uint16_t>(p0 + ((kProbabilityOne - p0) >> next_shift())); }
  void saw_one() { p0 = static_cast<uint16_t>(p0 - (p0 >> next_shift())); }
};

class BitEncoder {
 public:
  static constexpr bool kDecoding = false;

  explicit BitEncoder(std::vector<uint8_t>& out) : out_(out) {}

  // Inlined into the band coder's pixel loop (it was an out-of-line call per coded bit).
  [[gnu::always_inline]] bool bit(Probability& prob, bool value) {
    const uint32_t bound = (range_ >> kProbabilityBits) * prob.p0;
    if (!value) {
      range_ = bound;
      prob.saw_zero();
    } else {
      low_ += bound;
      range_ -= bound;
      prob.saw_one();
    }
    while (range_ < kTopValue) {
      range_ <<= 8;
      shift_low();
    }
    return value;
  }

  // Writes the remaining state; the coder must not be used afterwards.
  void finish() {
    for (int i = 0; i < 5; ++i) shift_low();
  }
  // Bytes the stream will have after finish() if no further bit is coded (an upper bound by at most one).
  size_t size_if_finished() const { return out_.size() - start_ + pending_ + 5; }

  // The coder's state between two bits. Bytes already written are final (a carry only reaches the cached and
  // pending bytes, which are part of the state), so restoring it after more bits were coded truncates the
  // output and continues, or finishes, exactly as if those bits had never been coded.
  struct State {
    size_t size = 0;
    uint64_t low = 0;
    uint32_t range = 0;
    uint8_t cache = 0;
    bool have_cache = false;
    size_t pending = 0;
  };
  State state() const { return State{out_.size(), low_, range_, cache_, have_cache_, pending_}; }
  void restore(const State& s) {
    out_.resize(s.size);
    low_ = s.low;
    range_ = s.range;
    cache_ = s.cache;
    have_cache_ = s.have_cache;
    pending_ = s.pending;
  }

 private:
  void shift_low() {
    if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
      const uint8_t carry = static_cast<uint8_t>(low_ >> 32);
      if (have_cache_) out_.push_back(static_cast<uint8_t>(cache_ + carry));
      for (; pending_ > 0; --pending_) out_.push_back(static_cast<uint8_t>(0xFF + carry));
      cache_ = static_cast<uint8_t>(low_ >> 24);
      have_cache_ = true;
    } else {
      ++pending_;
    }
    low_ = (low_ & 0x00FFFFFFu) << 8;
  }

  std::vector<uint8_t>& out_;
  size_t start_ = out_.size();
  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  bool have_cache_ = false;
  size_t pending_ = 0;
};

class BitDecoder {
 public:
  static constexpr bool kDecoding = true;

  // The encoder never writes LZMA's always-zero first byte, so the code starts with the stream's first four
  // bytes. Reading past the end yields zero bytes (counted in overrun()): hostile input costs bounded time and
  // decodes to garbage that the caller's checksum rejects.
  explicit BitDecoder(std::span<const uint8_t> in) : in_(in) {
    for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | next_byte();
  }

  [[gnu::always_inline]] bool bit(Probability& prob, bool /*value*/) {
    const uint32_t bound = (range_ >> kProbabilityBits) * prob.p0;
    bool value;
    if (code_ < bound) {
      range_ = bound;
      prob.saw_zero();
      value = false;
    } else {
      code_ -= bound;
      range_ -= bound;
      prob.saw_one();
      value = true;
    }
    while (range_ < kTopValue) {
      range_ <<= 8;
      code_ = (code_ << 8) | next_byte();
    }
    return value;
  }

  size_t overrun() const { return overrun_; }

 private:
  uint8_t next_byte() {
    if (pos_ < in_.size()) return in_[pos_++];
    ++overrun_;
    return 0;
  }

  std::span<const uint8_t> in_;
  size_t pos_ = 0;
  size_t overrun_ = 0;
  uint32_t code_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
};

}  // namespace dhr::codec_detail
