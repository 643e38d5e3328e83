// SequenceTracker: what the peer's datagram sequence numbers (protocol header, one counter per sender)
// say about the link: duplicates (same number twice) and gaps (numbers never seen, i.e. lost so far).
// A sliding window of the newest kWindow numbers makes it exact for reordering and duplication within
// that window, with fixed memory whatever arrives. Not thread-safe (the owner's lock covers it).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dhr::client {

class SequenceTracker {
 public:
  static constexpr size_t kDefaultWindow = 8192;
  enum class Result : uint8_t { kNew, kDuplicate, kTooOld };

  explicit SequenceTracker(size_t window = kDefaultWindow);  // window >= 64

  // u32 wrap-around is handled: a number is placed next to the newest one seen.
  Result add(uint32_t sequence);
  // A new session: the peer may start counting again. Totals are kept, the window is cleared.
  void restart();

  uint64_t unique() const { return unique_; }
  uint64_t duplicates() const { return duplicates_; }
  uint64_t too_old() const { return too_old_; }  // older than the window: not classified
  // Numbers between the oldest and newest seen (per session) that never arrived. Trailing losses
  // (after the newest number seen) are invisible until a newer number arrives.
  uint64_t missing() const;

 private:
  bool test(uint64_t n) const { return (bits_[(n % window_) / 64] >> (n % 64)) & 1u; }
  void set(uint64_t n) { bits_[(n % window_) / 64] |= uint64_t{1} << (n % 64); }
  void clear(uint64_t n) { bits_[(n % window_) / 64] &= ~(uint64_t{1} << (n % 64)); }

  size_t window_;
  std::vector<uint64_t> bits_;
  bool started_ = false;
  uint64_t first_ = 0;    // extended (64-bit) numbers of this session
  uint64_t highest_ = 0;
  uint64_t session_unique_ = 0;
  uint64_t carried_missing_ = 0;  // from earlier sessions
  uint64_t unique_ = 0;
  uint64_t duplicates_ = 0;
  uint64_t too_old_ = 0;
};

}  // namespace dhr::client
