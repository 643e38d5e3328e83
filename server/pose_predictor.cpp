// Constant-velocity / constant-angular-velocity extrapolation with a horizon cap and fallbacks.
#include "pose_predictor.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace dhr::server {
namespace {

// Extrapolates one eye from (t0, a) and (t1, b) by horizon seconds; false when implausible or non-finite.
bool extrapolate(const Pose& a, const Pose& b, double dt, double horizon, const PosePredictorConfig& config,
                 Pose& out) {
  const glm::dvec3 velocity = (b.position - a.position) / dt;
  glm::dquat delta = glm::normalize(b.orientation) * glm::conjugate(glm::normalize(a.orientation));  // world-frame rotation a -> b
  if (delta.w < 0.0) delta = -delta;                                 // shortest arc
  const glm::dvec3 v(delta.x, delta.y, delta.z);
  const double sin_half = glm::length(v);
  const double angle = 2.0 * std::atan2(sin_half, delta.w);
  const double angular_speed = angle / dt;
  if (!(glm::length(velocity) <= config.max_speed_mps) || !(angular_speed <= config.max_angular_speed_rps)) {
    return false;
  }
  out = b;
  if (horizon == 0.0) return true;  // exactly the newest pose
  out.position = b.position + velocity * horizon;
  out.orientation = glm::normalize(b.orientation);
  if (sin_half > 1e-12) {
    const glm::dquat step = glm::angleAxis(angular_speed * horizon, v / sin_half);
    out.orientation = glm::normalize(step * b.orientation);
  }
  return !validate_pose(out).has_value();  // finite, non-zero quaternion, plausible position
}

}  // namespace

PosePredictor::PosePredictor(const PosePredictorConfig& config) : config_(config) {
  if (config.history < 2 || config.max_horizon_ns < 0 || !(config.max_speed_mps > 0.0) ||
      !(config.max_angular_speed_rps > 0.0) || config.min_interval_ns < 0 || config.velocity_window_ns < 0 ||
      config.soft_horizon_ns < 0 || config.damping_tau_ns < 0) {
    throw std::invalid_argument("PosePredictorConfig: history >= 2, non-negative horizon, positive limits");
  }
}

bool PosePredictor::add(int64_t display_time_ns, const std::array<View, 2>& views) {
  for (const View& view : views) {
    if (validate_view(view)) return false;
  }
  if (!samples_.empty() && display_time_ns <= samples_.back().time_ns) return false;
  samples_.push_back(Sample{display_time_ns, views});  // kept bit-exact: a zero horizon returns them unchanged
  while (samples_.size() > config_.history) samples_.pop_front();
  return true;
}

PredictedViews PosePredictor::predict(int64_t target_time_ns) const {
  PredictedViews out;
  if (samples_.empty()) return out;
  const Sample& last = samples_.back();
  out.views = last.views;
  if (samples_.size() < 2) return out;
  size_t base = samples_.size() - 2;
  while (base > 0 && last.time_ns - samples_[base - 1].time_ns <= config_.velocity_window_ns) --base;
  const Sample& prev = samples_[base];
  const int64_t interval = last.time_ns - prev.time_ns;
  if (interval < config_.min_interval_ns) return out;

  int64_t horizon = std::max<int64_t>(0, target_time_ns - last.time_ns);
  if (config_.damping_tau_ns > 0 && horizon > config_.soft_horizon_ns) {
    const double tau = static_cast<double>(config_.damping_tau_ns);
    const double beyond = static_cast<double>(horizon - config_.soft_horizon_ns);
    horizon = config_.soft_horizon_ns + static_cast<int64_t>(std::llround(tau * (1.0 - std::exp(-beyond / tau))));
  }
  if (horizon > config_.max_horizon_ns) {
    horizon = config_.max_horizon_ns;
    out.capped = true;
  }
  const double dt = static_cast<double>(interval) * 1e-9;
  std::array<View, 2> predicted = last.views;
  for (size_t eye = 0; eye < 2; ++eye) {
    if (!extrapolate(prev.views[eye].pose, last.views[eye].pose, dt, static_cast<double>(horizon) * 1e-9, config_,
                     predicted[eye].pose)) {
      return out;  // fall back to the newest real poses
    }
  }
  out.views = predicted;
  out.horizon_ns = horizon;
  out.fell_back = false;
  return out;
}

int64_t PosePredictor::frame_period_ns() const {
  if (samples_.size() < 2) return 0;
  std::vector<int64_t> intervals;
  for (size_t i = 1; i < samples_.size(); ++i) intervals.push_back(samples_[i].time_ns - samples_[i - 1].time_ns);
  std::nth_element(intervals.begin(), intervals.begin() + static_cast<std::ptrdiff_t>(intervals.size() / 2),
                   intervals.end());
  return intervals[intervals.size() / 2];
}

int64_t round_up_to_frame_grid(int64_t horizon_ns, int64_t frame_period_ns) {
  if (horizon_ns <= 0) return 0;
  if (frame_period_ns < 1'000'000 || frame_period_ns > 100'000'000) return horizon_ns;
  // horizon_ns is bounded by the caller's clock values; the division first keeps the product in range.
  return (horizon_ns / frame_period_ns + (horizon_ns % frame_period_ns != 0 ? 1 : 0)) * frame_period_ns;
}

}  // namespace dhr::server
