// Clocks in integer nanoseconds. Network code takes a Clock so the same logic runs against the real
// monotonic clock (executables, loopback tests) and a VirtualClock (deterministic tests, dhr-eval).
#pragma once
#include <atomic>
#include <cstdint>

namespace dhr::net {

inline constexpr int64_t kNsPerMs = 1'000'000;
inline constexpr int64_t kNsPerSecond = 1'000'000'000;

// std::chrono::steady_clock in nanoseconds since its (unspecified, boot-based) epoch.
int64_t steady_now_ns();

class Clock {
 public:
  virtual ~Clock() = default;
  virtual int64_t now_ns() const = 0;
};

class SteadyClock final : public Clock {
 public:
  int64_t now_ns() const override { return steady_now_ns(); }
};

// Time moves only when the owner says so. Thread-safe (atomic), so a test thread can advance it while
// another reads it.
class VirtualClock final : public Clock {
 public:
  explicit VirtualClock(int64_t start_ns = 0) : now_(start_ns) {}
  int64_t now_ns() const override { return now_.load(std::memory_order_acquire); }
  void set_ns(int64_t t_ns) { now_.store(t_ns, std::memory_order_release); }
  void advance_ns(int64_t delta_ns) { now_.fetch_add(delta_ns, std::memory_order_acq_rel); }

 private:
  std::atomic<int64_t> now_;
};

}  // namespace dhr::net
