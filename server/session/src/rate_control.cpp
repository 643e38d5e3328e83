#include "session/rate_control.hpp"

#include <algorithm>

namespace dhr::server {

void SendRateController::on_report(int64_t now_ns, uint32_t client_received, uint64_t sent, uint64_t frames_traced) {
  if (!config_.enabled) return;
  if (!have_report_ || now_ns <= report_ns_ || sent < sent_ || frames_traced < frames_) {
    have_report_ = true;
    report_ns_ = now_ns;
    received_ = client_received;
    sent_ = sent;
    frames_ = frames_traced;
    return;
  }
  const double seconds = static_cast<double>(now_ns - report_ns_) * 1e-9;
  const double sent_delta = static_cast<double>(sent - sent_);
  const double received_delta = static_cast<double>(static_cast<uint32_t>(client_received - received_));
  const double frame_rate = static_cast<double>(frames_traced - frames_) / seconds;
  report_ns_ = now_ns;
  received_ = client_received;
  sent_ = sent;
  frames_ = frames_traced;
  if (sent_delta < 1.0) return;  // nothing sent: nothing learned
  if (frame_rate > 0.0) datagrams_per_frame_ = sent_delta / (frame_rate * seconds);
  last_loss_ = std::clamp(1.0 - received_delta / sent_delta, 0.0, 1.0);
  if (last_loss_ > config_.loss_high) {
    const double target = std::max(config_.min_fps, frame_rate * (1.0 - last_loss_) * config_.decrease);
    cap_fps_ = cap_fps_ ? std::min(*cap_fps_, target) : target;
    cap_fps_ = std::max(*cap_fps_, config_.min_fps);
    ++decreases_;
  } else if (last_loss_ < config_.loss_low && cap_fps_) {
    *cap_fps_ += config_.increase_fps_per_s * seconds;
    if (*cap_fps_ >= config_.max_fps) cap_fps_.reset();
  }
}

std::optional<double> SendRateController::pacing_dps() const {
  if (!cap_fps_ || datagrams_per_frame_ <= 0.0) return std::nullopt;
  return *cap_fps_ * datagrams_per_frame_ / 0.9;
}

int64_t SendRateController::next_due_ns(int64_t last_trace_ns) const {
  if (!cap_fps_) return last_trace_ns;
  return last_trace_ns + static_cast<int64_t>(1e9 / *cap_fps_);
}

}  // namespace dhr::server
