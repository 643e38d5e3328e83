// Network impairment: a deterministic model of a bad link (delay, jitter, random and bursty loss,
// reordering, duplication), so the system can be tested and demonstrated under a bad network without
// root or netem. docs/network.md describes the model; in short, per datagram, in send order:
//   1. burst state: Gilbert-Elliott two-state chain (good/bad), stepped once per datagram
//   2. loss: lost in the bad state with probability burst_loss_in_bad, and independently with
//      probability `loss` in either state
//   3. delay: delay_ms + jitter, jitter uniform in [-jitter_ms, +jitter_ms] or normal with standard
//      deviation jitter_ms (clamped to +-4 sigma); never below zero. Jitter alone does not reorder: like
//      most real links the model is FIFO, a datagram is never delivered before the one sent before it
//   4. reorder: with probability `reorder` the datagram is held back reorder_delay_ms extra and leaves
//      the FIFO, so datagrams sent after it within that time overtake it
//   5. duplicate: with probability `duplicate` a second copy is delivered, up to jitter_ms after the first
// Randomness is counter-based (a hash of seed, datagram index and decision), so each decision is a pure
// function of (seed, index) and enabling one impairment does not change the draws of another; only the
// burst state and the FIFO rule carry state from one datagram to the next. Identical on every platform
// (no <random> distributions, whose output is implementation-defined).
#pragma once
#include <array>
#include <cstdint>
#include <string>

namespace dhr::net {

enum class JitterDistribution : uint8_t { kUniform = 0, kNormal = 1 };

const char* to_string(JitterDistribution distribution);

struct ImpairmentParams {
  double delay_ms = 0.0;   // fixed one-way delay, 0..kMaxImpairmentDelayMs
  double jitter_ms = 0.0;  // uniform: half-width of the range; normal: standard deviation
  JitterDistribution jitter_distribution = JitterDistribution::kUniform;
  double loss = 0.0;                 // independent random loss probability, 0..1
  double burst_p_good_to_bad = 0.0;  // Gilbert-Elliott transition probabilities per datagram;
  double burst_p_bad_to_good = 1.0;  //   p_good_to_bad = 0 disables burst loss
  double burst_loss_in_bad = 1.0;    // loss probability in the bad state
  double reorder = 0.0;              // probability a datagram is held back (and overtaken), 0..1
  double reorder_delay_ms = 20.0;    // how long a reordered datagram is held back, > 0
  double duplicate = 0.0;            // probability a datagram is delivered twice, 0..1
  uint64_t seed = 1;

  bool active() const;           // false: the link is perfect and impairment can be bypassed
  std::string validate() const;  // "" when valid, else what is wrong (names the CLI option)
  std::string describe() const;  // one line, e.g. "delay=50ms jitter=20ms(uniform) loss=0.3 seed=1"
  // Long-run loss fraction: 1 - (1 - loss) * (1 - pi_bad * burst_loss_in_bad).
  double expected_loss() const;
  bool operator==(const ImpairmentParams&) const = default;
};

inline constexpr double kMaxImpairmentDelayMs = 60'000.0;

struct ImpairmentDecision {
  uint64_t sequence = 0;       // index of the datagram in send order, from 0
  uint8_t delivery_count = 0;  // 0 (lost), 1, or 2 (duplicated)
  std::array<int64_t, 2> delivery_ns{};  // [0] the datagram, [1] its duplicate; >= send time
  bool lost = false;
  bool lost_in_burst = false;  // lost while the burst chain was in the bad state
  bool reordered = false;
  bool duplicated = false;
};

struct ImpairmentStats {
  uint64_t sent = 0;        // datagrams offered to the link
  uint64_t lost = 0;        // lost_random + lost_burst
  uint64_t lost_random = 0;
  uint64_t lost_burst = 0;
  uint64_t duplicated = 0;  // extra copies scheduled (not counting the originals)
  uint64_t reordered = 0;   // datagrams held back (of those not lost)
  uint64_t deliveries = 0;  // copies scheduled for delivery: sent - lost + duplicated
  bool operator==(const ImpairmentStats&) const = default;
};

// Stateful (burst chain, FIFO rule) and not thread-safe: wrap it (SimulatedLink, ImpairedSender).
class ImpairmentModel {
 public:
  // Throws std::invalid_argument with validate()'s message when the params are invalid.
  explicit ImpairmentModel(const ImpairmentParams& params);

  // Decides the fate of the next datagram sent at send_time_ns (any clock; times should not go back).
  ImpairmentDecision next(int64_t send_time_ns);

  const ImpairmentParams& params() const { return params_; }
  const ImpairmentStats& stats() const { return stats_; }
  void reset();  // back to the state right after construction: same seed, same schedule

 private:
  int64_t jitter_ns(uint64_t sequence) const;

  ImpairmentParams params_;
  ImpairmentStats stats_;
  uint64_t sequence_ = 0;
  bool bad_state_ = false;
  bool have_in_order_ = false;
  int64_t last_in_order_ns_ = 0;  // delivery time of the newest datagram that kept its place
};

}  // namespace dhr::net
