// Constant-velocity / constant-angular-velocity extrapolation with a horizon cap and fallbacks.
#include "session/pose_predictor.hpp"

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

// Least-squares fit of y(t) = a + b t + c t^2 (t relative to the newest sample, seconds); returns y(h) - y(0),
// or false when the system is singular.
bool quadratic_change(const std::vector<double>& t, const std::vector<glm::dvec3>& y, double h, glm::dvec3& out) {
  double s[5] = {0, 0, 0, 0, 0};  // sums of t^k
  glm::dvec3 r[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};  // sums of y t^k
  for (size_t i = 0; i < t.size(); ++i) {
    double tk = 1.0;
    for (int k = 0; k < 5; ++k) {
      s[k] += tk;
      if (k < 3) r[k] += y[i] * tk;
      tk *= t[i];
    }
  }
  const glm::dmat3 m(s[0], s[1], s[2], s[1], s[2], s[3], s[2], s[3], s[4]);  // symmetric
  const double det = glm::determinant(m);
  if (!(std::abs(det) > 1e-18)) return false;
  const glm::dmat3 inv = glm::inverse(m);
  for (int axis = 0; axis < 3; ++axis) {
    const glm::dvec3 coef = inv * glm::dvec3(r[0][axis], r[1][axis], r[2][axis]);  // a, b, c
    out[axis] = coef[1] * h + coef[2] * h * h;
  }
  return std::isfinite(out.x + out.y + out.z);
}

glm::dvec3 rotation_vector(const glm::dquat& q_in) {
  glm::dquat q = glm::normalize(q_in);
  if (q.w < 0.0) q = -q;
  const glm::dvec3 v(q.x, q.y, q.z);
  const double s = glm::length(v);
  if (s < 1e-12) return v * 2.0;
  return v / s * (2.0 * std::atan2(s, q.w));
}

glm::dquat from_rotation_vector(const glm::dvec3& r) {
  const double angle = glm::length(r);
  if (angle < 1e-12) return glm::normalize(glm::dquat(1.0, r.x * 0.5, r.y * 0.5, r.z * 0.5));
  return glm::angleAxis(angle, r / angle);
}

}  // namespace

bool PosePredictor::extrapolate_quadratic(size_t eye, double horizon_s, Pose& out) const {
  const Sample& last = samples_.back();
  std::vector<double> t;
  std::vector<glm::dvec3> positions, rotations;
  const glm::dquat inv_last = glm::conjugate(glm::normalize(last.views[eye].pose.orientation));
  for (const Sample& s : samples_) {
    if (last.time_ns - s.time_ns > config_.quadratic_window_ns) continue;
    t.push_back(static_cast<double>(s.time_ns - last.time_ns) * 1e-9);
    positions.push_back(s.views[eye].pose.position - last.views[eye].pose.position);
    rotations.push_back(rotation_vector(glm::normalize(s.views[eye].pose.orientation) * inv_last));
  }
  if (t.size() < 3) return false;
  glm::dvec3 dp, dr;
  if (!quadratic_change(t, positions, horizon_s, dp) || !quadratic_change(t, rotations, horizon_s, dr)) return false;
  const double span = -t.front();
  if (span <= 0.0 || !(glm::length(dp) <= config_.max_speed_mps * std::max(horizon_s, span) * 2.0) ||
      !(glm::length(dr) <= config_.max_angular_speed_rps * std::max(horizon_s, span) * 2.0)) {
    return false;
  }
  out = last.views[eye].pose;
  out.position += dp;
  out.orientation = glm::normalize(from_rotation_vector(dr) * glm::normalize(last.views[eye].pose.orientation));
  return !validate_pose(out).has_value();
}

PosePredictor::PosePredictor(const PosePredictorConfig& config) : config_(config) {
  if (config.history < 2 || config.max_horizon_ns < 0 || !(config.max_speed_mps > 0.0) ||
      !(config.max_angular_speed_rps > 0.0) || config.min_interval_ns < 0 || config.velocity_window_ns < 0 ||
      config.soft_horizon_ns < 0 || config.damping_tau_ns < 0 || config.quadratic_window_ns < 0) {
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
    if (config_.quadratic_window_ns > 0 && horizon > 0 &&
        extrapolate_quadratic(eye, static_cast<double>(horizon) * 1e-9, predicted[eye].pose)) {
      continue;
    }
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
