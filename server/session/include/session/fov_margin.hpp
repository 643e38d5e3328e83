// Adaptive traced field of view (docs/server.md "Adaptive field of view"): the server widens the FOV it traces
// each eye with, per frame, by how far the views the client really displayed strayed from the views traced for
// them in the recent past. The measure folds in the head's angular and linear speed, the prediction horizon and
// the predictor's own error: for every traced frame the tracker remembers the views traced and the display time
// they were traced for (pose time + horizon); when the client's pose for that time arrives it measures, per
// side, how much of the displayed frustum (its corners at infinity and at parallax_depth_m) lies outside the
// traced view's FOV, in the traced view's tangent units. The margin is the largest shortfall per side over
// window_ns, times safety.
//
// The pixel budget stays the session's buffer (display + guard band): the part of the margin the guard band
// already covers costs nothing; beyond it the view's FOV is widened on that side, and the buffer's pixels spread
// over the wider view (coarser pixels) up to max_span_ratio times the view's tangent span per axis. A margin the
// guard band covers returns the view unchanged, bit for bit. The shards carry the widened view, and every user
// of a buffer builds its camera from that view (TracedFormat::camera), so clients need nothing new.
// Deterministic; not thread-safe (one per session, under the service's mutex).
#pragma once
#include "math/pose.hpp"
#include "math/projection.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>

namespace dhr::server {

struct FovMarginConfig {
  bool enabled = false;
  int64_t window_ns = 500'000'000;  // shortfalls remembered this long (by the displayed pose's time)
  double safety = 1.0;              // margin = safety * the largest shortfall in the window
  double parallax_depth_m = 1.0;    // translation measured on the frustum's corners at this depth (and at infinity)
  double max_span_ratio = 2.0;      // widened tangent span per axis at most this times the view's (>= 1)
  size_t max_pending = 64;          // traced frames awaiting their displayed pose (the oldest is dropped)
};

// Tangent-space extents per side beyond a view's FOV (>= 0; tangent units of that view).
struct SideTangents {
  double left = 0.0;
  double right = 0.0;
  double up = 0.0;
  double down = 0.0;
};

// How far the frustum of `shown` reaches beyond the FOV of `traced`, per side, in traced's tangent units: its
// four corner rays at infinity and the corner points at parallax_depth_m along shown's view axis. A corner at
// or behind traced's eye plane counts as kUnboundedShortfall on every side.
inline constexpr double kUnboundedShortfall = 1.0e3;
SideTangents coverage_shortfall(const View& traced, const View& shown, double parallax_depth_m);

class FovMarginTracker {
 public:
  explicit FovMarginTracker(const FovMarginConfig& config = {});

  // The views traced (before widening) for a display time: measured at once against the newest displayed pose
  // when that is at or after the target time (a horizon of 0), else when such a pose arrives.
  void traced(int64_t target_time_ns, const std::array<View, 2>& views);
  // The client's views for a display time: every traced frame whose target time is at or before it is measured
  // against them (the first displayed pose at or after the target). Invalid views, and poses not newer than
  // the newest one, are ignored.
  void observed(int64_t display_time_ns, const std::array<View, 2>& views);

  // The largest shortfall per side in the window, times safety; zero before any measurement.
  SideTangents margin(size_t eye) const;
  // `view` widened by the part of margin(eye) the format's guard band does not cover, within max_span_ratio.
  View widen(const View& view, size_t eye, const TracedFormat& format) const;

  size_t measurements() const { return measured_.size(); }
  void reset();
  const FovMarginConfig& config() const { return config_; }

 private:
  struct Pending {
    int64_t target_ns = 0;
    std::array<View, 2> views{};
  };
  struct Measured {
    int64_t time_ns = 0;
    std::array<SideTangents, 2> shortfall{};
  };
  FovMarginConfig config_;
  void measure(const std::array<View, 2>& traced, const std::array<View, 2>& shown, int64_t time_ns);

  std::deque<Pending> pending_;
  std::deque<Measured> measured_;
  bool have_observed_ = false;  // the newest displayed pose
  int64_t observed_time_ns_ = 0;
  std::array<View, 2> observed_views_{};
};

}  // namespace dhr::server
