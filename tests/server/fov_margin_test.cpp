// Adaptive traced field of view (server/session/include/session/fov_margin.hpp): the shortfall geometry against closed forms, the
// windowed margin, widening beyond the guard band within the span budget, and the service tracing and sending
// the widened views.
#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <stdexcept>

#include "session/fov_margin.hpp"
#include "service_test_rig.hpp"

namespace dhr::server {
namespace {

constexpr int64_t kMs = 1'000'000;

View straight_view(double half_angle = 0.6) {
  View v;
  v.pose.position = glm::dvec3(0.5, 1.6, -1.0);
  const float a = static_cast<float>(half_angle);
  v.fov = Fov{-a, a, a, -a};
  return v;
}

// The view turned right (toward its own +X) by `yaw` radians: a rotation about its +Y by -yaw.
View turned_right(View v, double yaw) {
  v.pose.orientation = v.pose.orientation * glm::angleAxis(-yaw, glm::dvec3(0.0, 1.0, 0.0));
  return v;
}

TEST(CoverageShortfall, ZeroForTheSameViewAndAViewInside) {
  const View v = straight_view();
  const SideTangents same = coverage_shortfall(v, v, 1.0);
  EXPECT_EQ(same.left, 0.0);
  EXPECT_EQ(same.right, 0.0);
  EXPECT_EQ(same.up, 0.0);
  EXPECT_EQ(same.down, 0.0);
  const SideTangents inside = coverage_shortfall(v, straight_view(0.3), 1.0);
  EXPECT_EQ(inside.left + inside.right + inside.up + inside.down, 0.0);
}

TEST(CoverageShortfall, AYawNeedsTheTurnedEdgeOnThatSideOnly) {
  const double half = 0.6, yaw = 0.1;
  const View traced = straight_view(half);
  const SideTangents s = coverage_shortfall(traced, turned_right(traced, yaw), 0.0);
  // The right edge of the turned view is at angle half + yaw: its corners land at x = tan(half + yaw).
  EXPECT_NEAR(s.right, std::tan(half + yaw) - std::tan(half), 1e-7);  // the FOV is float
  EXPECT_EQ(s.left, 0.0);
  EXPECT_GT(s.up, 0.0);  // the far corners rise in the traced image (perspective), symmetric up and down
  EXPECT_NEAR(s.up, s.down, 1e-12);
  // Turned left: the mirror image.
  const SideTangents l = coverage_shortfall(traced, turned_right(traced, -yaw), 0.0);
  EXPECT_NEAR(l.left, s.right, 1e-12);
  EXPECT_EQ(l.right, 0.0);
}

TEST(CoverageShortfall, TranslationCountsAtTheParallaxDepth) {
  const View traced = straight_view();
  View moved = traced;
  moved.pose.position.x += 0.05;
  moved.pose.position.y -= 0.02;
  const SideTangents s = coverage_shortfall(traced, moved, 2.0);
  EXPECT_NEAR(s.right, 0.05 / 2.0, 1e-12);
  EXPECT_NEAR(s.down, 0.02 / 2.0, 1e-12);
  EXPECT_EQ(s.left, 0.0);
  EXPECT_EQ(s.up, 0.0);
  // Depth 0: rotation only, a pure translation needs nothing.
  const SideTangents r = coverage_shortfall(traced, moved, 0.0);
  EXPECT_EQ(r.left + r.right + r.up + r.down, 0.0);
}

TEST(CoverageShortfall, ACornerBehindTheTracedEyeIsUnbounded) {
  const View traced = straight_view();
  const SideTangents s = coverage_shortfall(traced, turned_right(traced, 3.0), 0.0);
  EXPECT_EQ(s.left, kUnboundedShortfall);
  EXPECT_EQ(s.down, kUnboundedShortfall);
}

TEST(FovMarginTracker, MeasuresWhenTheDisplayedPoseArrivesAndForgetsAfterTheWindow) {
  FovMarginConfig config;
  config.enabled = true;
  config.window_ns = 200 * kMs;
  config.parallax_depth_m = 0.0;
  FovMarginTracker tracker(config);
  const View v = straight_view();
  tracker.traced(100 * kMs, {v, v});
  tracker.observed(90 * kMs, {turned_right(v, 0.2), turned_right(v, 0.2)});  // before the target: nothing
  EXPECT_EQ(tracker.measurements(), 0u);
  EXPECT_EQ(tracker.margin(0).right, 0.0);
  tracker.observed(100 * kMs, {turned_right(v, 0.1), turned_right(v, -0.05)});
  ASSERT_EQ(tracker.measurements(), 1u);
  EXPECT_NEAR(tracker.margin(0).right, std::tan(0.7) - std::tan(0.6), 1e-7);  // float FOV
  EXPECT_EQ(tracker.margin(0).left, 0.0);
  EXPECT_NEAR(tracker.margin(1).left, std::tan(0.65) - std::tan(0.6), 1e-7);
  EXPECT_EQ(tracker.margin(2).right, 0.0);  // no such eye
  // Still within the window at 300 ms, gone after it.
  tracker.observed(300 * kMs, {v, v});
  EXPECT_EQ(tracker.measurements(), 1u);
  tracker.observed(301 * kMs, {v, v});
  EXPECT_EQ(tracker.measurements(), 0u);
  EXPECT_EQ(tracker.margin(0).right, 0.0);
  // A target at or before the newest displayed pose (a horizon of 0) is measured at once against that pose.
  tracker.traced(301 * kMs, {turned_right(v, -0.1), v});
  ASSERT_EQ(tracker.measurements(), 1u);
  EXPECT_NEAR(tracker.margin(0).right, std::tan(0.7) - std::tan(0.6), 1e-7);
  EXPECT_EQ(tracker.margin(1).right, 0.0);
  // A displayed pose older than the newest is ignored.
  tracker.traced(400 * kMs, {v, v});
  tracker.observed(300 * kMs, {turned_right(v, 0.3), turned_right(v, 0.3)});
  EXPECT_EQ(tracker.measurements(), 1u);
}

TEST(FovMarginTracker, WidensOnlyBeyondTheGuardBandAndWithinTheSpanBudget) {
  FovMarginConfig config;
  config.enabled = true;
  config.parallax_depth_m = 0.0;
  config.max_span_ratio = 1.5;
  const View v = straight_view(0.6);
  const double t = std::tan(0.6);
  const TracedFormat format{Extent{100, 100}, GuardBand{10, 10}};  // the band covers 0.2 * t per side
  const auto tracker_after = [&](double yaw) {
    FovMarginTracker tracker(config);
    tracker.traced(10 * kMs, {v, v});
    tracker.observed(10 * kMs, {turned_right(v, yaw), turned_right(v, yaw)});
    return tracker;
  };
  // A small turn the guard band covers: the view comes back bit for bit.
  {
    const FovMarginTracker tracker = tracker_after(0.02);
    ASSERT_LT(tracker.margin(0).right, 0.2 * t);
    const View w = tracker.widen(v, 0, format);
    EXPECT_EQ(w.fov.angle_right, v.fov.angle_right);
    EXPECT_EQ(w.fov.angle_left, v.fov.angle_left);
    EXPECT_EQ(w.fov.angle_up, v.fov.angle_up);
  }
  // A larger turn: the right side grows by the margin minus the band, the left stays.
  {
    const FovMarginTracker tracker = tracker_after(0.15);
    const double m = tracker.margin(0).right;
    ASSERT_GT(m, 0.2 * t);
    const View w = tracker.widen(v, 0, format);
    EXPECT_NEAR(std::tan(static_cast<double>(w.fov.angle_right)), t + m - 0.2 * t, 1e-6);
    EXPECT_EQ(w.fov.angle_left, v.fov.angle_left);
    // Disabled: unchanged.
    FovMarginConfig off = config;
    off.enabled = false;
    FovMarginTracker disabled(off);
    disabled.traced(10 * kMs, {v, v});
    disabled.observed(10 * kMs, {turned_right(v, 0.15), turned_right(v, 0.15)});
    EXPECT_EQ(disabled.widen(v, 0, format).fov.angle_right, v.fov.angle_right);
  }
  // A turn beyond the budget: the span stops at max_span_ratio times the view's.
  {
    const FovMarginTracker tracker = tracker_after(0.6);
    const View w = tracker.widen(v, 0, format);
    const Tangents a = Tangents::from_fov(v.fov), b = Tangents::from_fov(w.fov);
    EXPECT_NEAR(b.width(), 1.5 * a.width(), 1e-6);
    EXPECT_FALSE(validate_view(w).has_value());
  }
}

TEST(FovMarginTracker, RejectsUnusableConfigsAndIgnoresBadViews) {
  FovMarginConfig bad;
  bad.max_span_ratio = 0.5;
  EXPECT_THROW(FovMarginTracker{bad}, std::invalid_argument);
  bad = {};
  bad.window_ns = 0;
  EXPECT_THROW(FovMarginTracker{bad}, std::invalid_argument);
  bad = {};
  bad.safety = std::nan("");
  EXPECT_THROW(FovMarginTracker{bad}, std::invalid_argument);
  FovMarginConfig config;
  config.enabled = true;
  FovMarginTracker tracker(config);
  View nan_view = straight_view();
  nan_view.pose.position.x = std::nan("");
  tracker.traced(10 * kMs, {nan_view, nan_view});
  tracker.observed(10 * kMs, {straight_view(), straight_view()});
  EXPECT_EQ(tracker.measurements(), 0u);
  tracker.traced(20 * kMs, {straight_view(), straight_view()});
  tracker.observed(20 * kMs, {nan_view, nan_view});
  EXPECT_EQ(tracker.measurements(), 0u);
  EXPECT_TRUE(std::isnan(tracker.widen(nan_view, 0, TracedFormat{Extent{8, 8}, GuardBand{}}).pose.position.x));
}

using test_rig::VisibilityServiceTest;
using test_rig::bookmark_views;

// A head turning right at a constant rate with a fixed 100 ms horizon and no prediction: once the first traced
// frame's displayed pose has arrived, the shards carry views widened on the right, and their buffers are exactly
// what the tracer gives for those views.
TEST_F(VisibilityServiceTest, AdaptiveFovTracesAndSendsTheWidenedViews) {
  config_.adaptive_fov.enabled = true;
  config_.predict_horizon_ns = 99 * kMs;  // 9 frames of 11 ms (send_pose's display times)
  make_service();
  Welcome w;
  const uint64_t t = connect(peer(1), 1, &w);
  const auto turned = [](uint64_t frame) {
    std::array<View, 2> views = bookmark_views(0);
    for (View& v : views) v = turned_right(v, 0.03 * static_cast<double>(frame));  // 2.7 rad/s
    return views;
  };
  std::array<View, 2> traced_views{};
  std::array<VisibilityBuffer, 2> got;
  for (uint64_t frame = 1; frame <= 12; ++frame) {
    send_pose(t, peer(1), frame, turned(frame));
    EXPECT_EQ(service_->process_pending(), 1u);
    got = reassemble(w, shards_of(drain()[peer(1)]), frame, &traced_views);
  }
  // Frames 10..12 saw the shortfall of frames 1..3 (turned 0.27 rad further right than traced).
  const View sent = turned(12)[0];
  EXPECT_GT(traced_views[0].fov.angle_right, sent.fov.angle_right + 0.05f);
  EXPECT_EQ(traced_views[0].fov.angle_left, sent.fov.angle_left);
  EXPECT_EQ(traced_views[0].pose.position, sent.pose.position);
  for (int e = 0; e < 2; ++e) EXPECT_EQ(got[e], trace_directly(traced_views[e]));
  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.eyes_fov_widened, 6u);  // both eyes of frames 10, 11, 12
  EXPECT_GT(s.fov_span_ratio, 24.0);
  EXPECT_EQ(s.frames_predicted, 0u);
}

}  // namespace
}  // namespace dhr::server
