// Server-side pose prediction: the server traces each eye for the pose it predicts at the time the result
// will be displayed, extrapolated from the client's recent poses. Model: constant linear velocity and
// constant angular velocity (about a world-frame axis) per eye, estimated from the newest pose and the oldest
// one within velocity_window_ns (the two newest by default).
// The horizon (target time - newest pose's time) is capped at max_horizon_ns and reported; a prediction
// that is non-finite or implausible (speed or angular speed above the limits) falls back to the newest
// real pose, and so does a history of fewer than two poses. Deterministic; not thread-safe.
#pragma once
#include "math/pose.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>

namespace dhr::server {

struct PosePredictorConfig {
  // The horizon is clamped to [0, this]. A longer cap helps some traces and hurts others (docs/evaluation.md,
  // "Horizon cap": the sweep that kept 100 ms).
  int64_t max_horizon_ns = 100'000'000;
  size_t history = 16;                   // poses kept (for the frame-period estimate); >= 2
  double max_speed_mps = 5.0;            // faster eye motion is treated as a glitch (fall back)
  double max_angular_speed_rps = 12.6;   // ~720 deg/s, above the fastest head turns measured in XR
  // Poses closer in time than this are too close for a velocity estimate (clock jitter dominates).
  int64_t min_interval_ns = 1'000'000;
  // Velocities are measured from the newest pose back to the oldest pose held that is at most this much
  // older (a longer baseline averages out tracking noise and the trace's resampling steps); 0: the two
  // newest poses.
  int64_t velocity_window_ns = 0;
  // Beyond soft_horizon_ns the extrapolation is damped: a horizon h > soft becomes
  // soft + damping_tau_ns * (1 - exp(-(h - soft) / damping_tau_ns)), then capped at max_horizon_ns. 0: off.
  // Off by default: dhr-eval measured a big gain at 200 ms RTT but a loss at 100 ms (docs/evaluation.md).
  int64_t soft_horizon_ns = 0;
  int64_t damping_tau_ns = 0;
  // > 0: instead of the two-pose velocity, a least-squares quadratic in time (constant acceleration) is fitted
  // to every pose within this window (at least 3; fewer, a singular system or an implausible fit: the velocity
  // model) per eye, to the positions and to
  // the orientations' rotation vectors relative to the newest; the prediction moves the newest pose by the
  // fit's change from the newest time to the target. 0: off (default; docs/evaluation.md measured it).
  int64_t quadratic_window_ns = 0;
};

struct PredictedViews {
  std::array<View, 2> views{};
  int64_t horizon_ns = 0;  // the horizon actually used (after the cap); 0 on fallback
  bool fell_back = true;   // true: views are the newest real poses (or default views with no history)
  bool capped = false;     // the requested horizon exceeded max_horizon_ns
};

class PosePredictor {
 public:
  explicit PosePredictor(const PosePredictorConfig& config = {});

  // Adds the client's views for a display time. Poses must come in display-time order: a sample that is
  // not newer than the newest one, or whose poses or FOVs are invalid (non-finite, zero quaternion), is
  // ignored and false returned.
  bool add(int64_t display_time_ns, const std::array<View, 2>& views);

  // The views predicted for target_time_ns. FOVs are the newest ones.
  PredictedViews predict(int64_t target_time_ns) const;

  // Median interval between the poses held (0 with fewer than two): the client's frame period.
  int64_t frame_period_ns() const;
  size_t size() const { return samples_.size(); }
  int64_t newest_time_ns() const { return samples_.empty() ? 0 : samples_.back().time_ns; }
  void reset() { samples_.clear(); }
  const PosePredictorConfig& config() const { return config_; }

 private:
  struct Sample {
    int64_t time_ns = 0;
    std::array<View, 2> views{};
  };
  bool extrapolate_quadratic(size_t eye, double horizon_s, Pose& out) const;

  PosePredictorConfig config_;
  std::deque<Sample> samples_;
};

// The automatic horizon on the client's frame grid: a result that arrives `horizon_ns` after a pose's
// display time is shown at the first client frame after that, a whole number of frame periods after the
// pose's own display time. A frame period outside [1 ms, 100 ms] (unknown, or implausible for a headset)
// leaves the horizon unchanged; a negative horizon becomes 0.
int64_t round_up_to_frame_grid(int64_t horizon_ns, int64_t frame_period_ns);

}  // namespace dhr::server
