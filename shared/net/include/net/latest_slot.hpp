// LatestSlot<T>: hand the newest value from one thread to another without either ever blocking.
// The client's receive thread publishes each newly (partly) reassembled visibility buffer; the render
// loop takes the newest one each frame. Values that are overwritten before the reader looks are simply
// skipped (counted), which is exactly "newest wins".
//
// Lock-free triple buffer: the writer owns one buffer, the reader owns one, and the third sits in the
// middle. publish() swaps the writer's buffer with the middle one; fetch() swaps the middle one with
// the reader's when it holds something newer. Both are a single atomic exchange (wait-free). Buffers are
// recycled, so a T holding vectors keeps its capacity and steady-state operation does not allocate.
//
// Contract: at most one writer thread and one reader thread at a time (either may change over time if
// the hand-over is synchronized). T must be default-constructible and movable/swappable.
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <utility>

namespace dhr::net {

template <class T>
class LatestSlot {
 public:
  LatestSlot() = default;
  LatestSlot(const LatestSlot&) = delete;
  LatestSlot& operator=(const LatestSlot&) = delete;

  // ---- writer side ----
  // The writer's private buffer: fill it in place (it holds an older value, reuse its storage), then
  // publish(). Valid until the next publish().
  T& write_buffer() { return buffers_[back_]; }

  // Makes the write buffer the newest value. Never blocks.
  void publish() {
    const uint8_t previous = middle_.exchange(static_cast<uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = static_cast<uint8_t>(previous & kIndexMask);
    if (previous & kFresh) overwritten_.fetch_add(1, std::memory_order_relaxed);
    published_.fetch_add(1, std::memory_order_relaxed);
  }

  void publish(T value) {
    write_buffer() = std::move(value);
    publish();
  }

  // ---- reader side ----
  // Takes the newest published value into the reader's buffer if one arrived since the last fetch.
  // Returns true when read_buffer() changed. Never blocks.
  bool fetch() {
    if (!(middle_.load(std::memory_order_relaxed) & kFresh)) return false;
    const uint8_t previous = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = static_cast<uint8_t>(previous & kIndexMask);
    has_value_ = true;
    return true;
  }

  // The newest value fetched so far (a default-constructed T before the first successful fetch).
  const T& read_buffer() const { return buffers_[front_]; }
  T& read_buffer() { return buffers_[front_]; }
  bool has_value() const { return has_value_; }

  // fetch(), then swap the newest value into `out` (no copy). Returns false, leaving `out` untouched,
  // when nothing new was published. The storage `out` held goes back to the writer later (and
  // read_buffer() holds it until the next fetch), so storage is recycled rather than reallocated.
  bool take(T& out) {
    if (!fetch()) return false;
    using std::swap;
    swap(out, buffers_[front_]);
    return true;
  }

  // ---- statistics (any thread) ----
  uint64_t published_count() const { return published_.load(std::memory_order_relaxed); }
  // Values replaced by a newer one before the reader fetched them.
  uint64_t overwritten_count() const { return overwritten_.load(std::memory_order_relaxed); }

 private:
  static constexpr uint8_t kIndexMask = 0x3;
  static constexpr uint8_t kFresh = 0x4;

  // Writer state, reader state and the shared index on separate cache lines (no false sharing).
  std::array<T, 3> buffers_{};
  alignas(64) uint8_t back_ = 0;  // writer-owned index
  std::atomic<uint64_t> published_{0};
  std::atomic<uint64_t> overwritten_{0};
  alignas(64) uint8_t front_ = 1;  // reader-owned index
  bool has_value_ = false;         // reader-owned
  alignas(64) std::atomic<uint8_t> middle_{2};  // index | kFresh while it holds an unread value
};

}  // namespace dhr::net
