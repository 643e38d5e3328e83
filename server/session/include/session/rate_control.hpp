// SendRateController: how often one session may be traced, from what its client reports receiving
// (docs/reliability.md, "A real bottleneck"). Each client Heartbeat carries the client's count of datagrams
// received; against the datagrams the server sent the session over the same interval it gives the loss on
// the way. Loss above `loss_high` (a queue overflowing somewhere, e.g. a token bucket) caps the session's
// trace rate just under what got through; loss below `loss_low` lifts the cap additively until it is gone.
// The server never queues poses: a pose that is not due stays pending and is replaced by newer ones. While a
// cap holds, a frame's datagrams are paced over the cap's frame interval (pacing_dps) instead of leaving back
// to back: a burst that overflows a small queue on the way would lose part of every frame.
#pragma once
#include <cstdint>
#include <optional>

namespace dhr::server {

struct RateControlConfig {
  bool enabled = false;       // ServiceConfig's default; dhr-server turns it on (--no-rate-adapt: off)
  double loss_high = 0.10;    // loss over a report interval above this lowers the cap
  double loss_low = 0.02;     // ... below this raises it
  double decrease = 0.85;     // new cap = delivered frame rate * decrease
  double increase_fps_per_s = 2.0;   // additive increase per second of low loss
  double min_fps = 2.0;
  double max_fps = 240.0;     // a cap above this is dropped (no limit)
};

class SendRateController {
 public:
  explicit SendRateController(const RateControlConfig& config = {}) : config_(config) {}

  // A client report at `now_ns`: its cumulative datagrams received (Heartbeat, 32-bit, may wrap), and the
  // server's cumulative datagrams sent to it and frames traced for it.
  void on_report(int64_t now_ns, uint32_t client_received, uint64_t sent, uint64_t frames_traced);

  // Whether a trace may start at `now_ns` when the last one started at `last_trace_ns`, and when it may.
  bool due(int64_t now_ns, int64_t last_trace_ns) const { return now_ns >= next_due_ns(last_trace_ns); }
  int64_t next_due_ns(int64_t last_trace_ns) const;

  std::optional<double> cap_fps() const { return cap_fps_; }
  // Datagrams per second to pace a capped session's frames at (a frame's datagrams over 90 % of the cap's
  // frame interval, from the datagrams per frame of the last report); std::nullopt without a cap.
  std::optional<double> pacing_dps() const;
  double last_loss() const { return last_loss_; }
  uint64_t decreases() const { return decreases_; }

 private:
  RateControlConfig config_;
  bool have_report_ = false;
  int64_t report_ns_ = 0;
  uint32_t received_ = 0;
  uint64_t sent_ = 0;
  uint64_t frames_ = 0;
  std::optional<double> cap_fps_;
  double last_loss_ = 0.0;
  uint64_t decreases_ = 0;
  double datagrams_per_frame_ = 0.0;
};

}  // namespace dhr::server
