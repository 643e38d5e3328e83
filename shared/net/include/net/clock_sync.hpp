// Clock-offset estimation between client and server from NTP-style timestamp exchanges, so that times
// stamped on the server (trace start/end, send) can be placed on the client's timeline for per-frame
// response-time breakdowns.
//
// One exchange: the client sends at t0 (client clock), the server receives at t1 and replies at t2
// (server clock), the client receives the reply at t3 (client clock). With one-way delays d_up, d_down:
//   offset = ((t1 - t0) + (t2 - t3)) / 2 = true_offset + (d_up - d_down) / 2
//   rtt    = (t3 - t0) - (t2 - t1)       = d_up + d_down
// so |offset - true_offset| <= rtt / 2 whatever the asymmetry. Queueing inflates rtt and usually the
// asymmetry, so the estimator keeps a window of recent samples and trusts the one with the smallest rtt.
// "offset" is always server clock minus client clock. The roles are only names: the server can run the
// same estimator with itself as "client".
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace dhr::net {

struct ClockSample {
  int64_t t0_ns = 0;  // client send (client clock)
  int64_t t1_ns = 0;  // server receive (server clock)
  int64_t t2_ns = 0;  // server send (server clock)
  int64_t t3_ns = 0;  // client receive (client clock)
};

struct OffsetEstimate {
  int64_t offset_ns = 0;  // server clock - client clock
  int64_t rtt_ns = 0;     // network round trip, server hold time excluded
  bool operator==(const OffsetEstimate&) const = default;
};

// nullopt when the sample is impossible for monotonic clocks (t3 < t0, t2 < t1, negative rtt) or the
// arithmetic would overflow.
std::optional<OffsetEstimate> offset_from_sample(const ClockSample& sample);

// Not thread-safe: one owner (e.g. the receive thread) adds samples; publish estimate() elsewhere.
class ClockOffsetEstimator {
 public:
  static constexpr size_t kDefaultWindow = 16;

  explicit ClockOffsetEstimator(size_t window = kDefaultWindow);  // window 0 is treated as 1

  // Returns false (and counts the sample as rejected) when offset_from_sample rejects it.
  bool add_sample(const ClockSample& sample);
  // The Heartbeat form of a sample: the peer echoes our send time (t0), reports how long it held our
  // message before replying (t2 - t1) and its send time (t2); we received the reply at t3.
  bool add_echo(int64_t echo_time_ns, int64_t echo_delay_ns, int64_t peer_send_time_ns,
                int64_t receive_time_ns);

  bool has_estimate() const { return best_.has_value(); }
  std::optional<OffsetEstimate> estimate() const { return best_; }
  int64_t offset_ns() const { return best_ ? best_->offset_ns : 0; }  // 0 before the first sample
  int64_t rtt_ns() const { return best_ ? best_->rtt_ns : 0; }
  // Causality bound on the error of offset_ns(): rtt / 2 (rounded up).
  int64_t uncertainty_ns() const { return best_ ? (best_->rtt_ns + 1) / 2 : 0; }

  int64_t server_to_client_ns(int64_t server_ns) const { return server_ns - offset_ns(); }
  int64_t client_to_server_ns(int64_t client_ns) const { return client_ns + offset_ns(); }

  size_t window() const { return window_; }
  size_t samples_in_window() const { return samples_.size(); }
  uint64_t accepted_count() const { return accepted_; }
  uint64_t rejected_count() const { return rejected_; }
  void reset();

 private:
  size_t window_;
  std::vector<OffsetEstimate> samples_;  // ring buffer, oldest overwritten first
  size_t next_ = 0;
  std::optional<OffsetEstimate> best_;
  uint64_t accepted_ = 0;
  uint64_t rejected_ = 0;
};

}  // namespace dhr::net
