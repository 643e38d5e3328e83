// Adaptive traced field of view: shortfall measurement, the windowed margin and the widened view.
#include "session/fov_margin.hpp"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dhr::server {
namespace {

// Tangents are kept below tan(80 degrees): the widened view stays a valid FOV with room for the guard band.
constexpr double kMaxTangent = 5.67;

}  // namespace

SideTangents coverage_shortfall(const View& traced, const View& shown, double parallax_depth_m) {
  const Tangents t = Tangents::from_fov(traced.fov);
  const Tangents s = Tangents::from_fov(shown.fov);
  const glm::dquat to_traced = glm::conjugate(glm::normalize(traced.pose.orientation));
  const glm::dquat shown_q = glm::normalize(shown.pose.orientation);
  double min_x = t.left, max_x = t.right, min_y = t.down, max_y = t.up;
  bool unbounded = false;
  const auto include = [&](const glm::dvec3& p) {  // p in traced's eye space
    if (!(-p.z > 1e-6)) {
      unbounded = true;
      return;
    }
    const double x = p.x / -p.z, y = p.y / -p.z;
    min_x = std::min(min_x, x);
    max_x = std::max(max_x, x);
    min_y = std::min(min_y, y);
    max_y = std::max(max_y, y);
  };
  for (const double tx : {s.left, s.right}) {
    for (const double ty : {s.down, s.up}) {
      const glm::dvec3 dir_world = shown_q * glm::dvec3(tx, ty, -1.0);
      include(to_traced * dir_world);  // at infinity: the direction alone
      if (parallax_depth_m > 0.0) {
        include(to_traced * (shown.pose.position + parallax_depth_m * dir_world - traced.pose.position));
      }
    }
  }
  if (unbounded || !std::isfinite(min_x + max_x + min_y + max_y)) {
    return SideTangents{kUnboundedShortfall, kUnboundedShortfall, kUnboundedShortfall, kUnboundedShortfall};
  }
  return SideTangents{t.left - min_x, max_x - t.right, max_y - t.up, t.down - min_y};
}

FovMarginTracker::FovMarginTracker(const FovMarginConfig& config) : config_(config) {
  if (config.window_ns <= 0 || !(config.safety >= 0.0) || !(config.parallax_depth_m >= 0.0) ||
      !(config.max_span_ratio >= 1.0) || !std::isfinite(config.max_span_ratio) || config.max_pending == 0) {
    throw std::invalid_argument("FovMarginConfig: window > 0, safety and parallax depth >= 0, span ratio >= 1");
  }
}

void FovMarginTracker::traced(int64_t target_time_ns, const std::array<View, 2>& views) {
  for (const View& view : views)
    if (validate_view(view)) return;
  if (have_observed_ && target_time_ns <= observed_time_ns_) {  // the displayed pose is already here
    measure(views, observed_views_, observed_time_ns_);
    return;
  }
  pending_.push_back(Pending{target_time_ns, views});
  while (pending_.size() > config_.max_pending) pending_.pop_front();
}

void FovMarginTracker::measure(const std::array<View, 2>& traced, const std::array<View, 2>& shown, int64_t time_ns) {
  Measured m{time_ns, {}};
  for (size_t e = 0; e < 2; ++e) m.shortfall[e] = coverage_shortfall(traced[e], shown[e], config_.parallax_depth_m);
  measured_.push_back(m);
}

void FovMarginTracker::observed(int64_t display_time_ns, const std::array<View, 2>& views) {
  for (const View& view : views)
    if (validate_view(view)) return;
  if (have_observed_ && display_time_ns <= observed_time_ns_) return;  // not newer: out of order
  have_observed_ = true;
  observed_time_ns_ = display_time_ns;
  observed_views_ = views;
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (it->target_ns > display_time_ns) {
      ++it;
      continue;
    }
    measure(it->views, views, display_time_ns);
    it = pending_.erase(it);
  }
  while (!measured_.empty() && measured_.front().time_ns < display_time_ns - config_.window_ns) measured_.pop_front();
}

SideTangents FovMarginTracker::margin(size_t eye) const {
  SideTangents out;
  if (eye > 1) return out;
  for (const Measured& m : measured_) {
    const SideTangents& s = m.shortfall[eye];
    out.left = std::max(out.left, s.left);
    out.right = std::max(out.right, s.right);
    out.up = std::max(out.up, s.up);
    out.down = std::max(out.down, s.down);
  }
  out.left *= config_.safety;
  out.right *= config_.safety;
  out.up *= config_.safety;
  out.down *= config_.safety;
  return out;
}

View FovMarginTracker::widen(const View& view, size_t eye, const TracedFormat& format) const {
  if (!config_.enabled || format.display.width == 0 || format.display.height == 0 || validate_view(view)) return view;
  const SideTangents m = margin(eye);
  const Tangents t = Tangents::from_fov(view.fov);
  // What the guard band covers per side, in tangent units at the display's pixel pitch.
  const double guard_x = format.guard.x * t.width() / format.display.width;
  const double guard_y = format.guard.y * t.height() / format.display.height;
  double left = std::max(0.0, m.left - guard_x), right = std::max(0.0, m.right - guard_x);
  double up = std::max(0.0, m.up - guard_y), down = std::max(0.0, m.down - guard_y);
  if (left + right + up + down == 0.0) return view;
  const auto fit = [&](double& a, double& b, double span) {  // a + b <= (ratio - 1) * span
    const double room = (config_.max_span_ratio - 1.0) * span;
    if (a + b > room) {
      const double k = room / (a + b);
      a *= k;
      b *= k;
    }
  };
  fit(left, right, t.width());
  fit(up, down, t.height());
  // Never narrower than the view (a view already beyond kMaxTangent keeps its own side).
  Tangents w{std::min(t.left, std::max(t.left - left, -kMaxTangent)), std::max(t.right, std::min(t.right + right, kMaxTangent)),
             std::max(t.up, std::min(t.up + up, kMaxTangent)), std::min(t.down, std::max(t.down - down, -kMaxTangent))};
  View out = view;
  out.fov = w.to_fov();
  if (validate_view(out)) return view;
  return out;
}

void FovMarginTracker::reset() {
  pending_.clear();
  measured_.clear();
  have_observed_ = false;
}

}  // namespace dhr::server
