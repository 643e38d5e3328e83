// Server-side pose prediction (server/session/include/session/pose_predictor.hpp): exact on constant linear and angular velocity,
// horizon cap, fallbacks on short history, implausible motion and bad input.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "session/pose_predictor.hpp"

namespace dhr::server {
namespace {

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kFrame = 11'111'111;  // 90 Hz

const glm::dvec3 kVelocity{0.3, -0.1, 0.25};            // m/s
const glm::dvec3 kAxis = glm::normalize(glm::dvec3(0.2, 1.0, -0.1));
constexpr double kAngularSpeed = 1.5;                   // rad/s
const glm::dvec3 kEyeOffset{0.0315, 0.0, 0.0};

// Eye `eye` at time t (ns) of a motion with constant linear and angular velocity.
Pose moving_pose(int64_t t, int eye) {
  const double s = static_cast<double>(t) * 1e-9;
  Pose pose;
  pose.position = glm::dvec3(1.0, 1.6, -2.0) + (eye == 0 ? -kEyeOffset : kEyeOffset) + kVelocity * s;
  pose.orientation = glm::angleAxis(kAngularSpeed * s, kAxis) * glm::angleAxis(0.3, glm::dvec3(0.0, 1.0, 0.0));
  return pose;
}

std::array<View, 2> moving_views(int64_t t) {
  std::array<View, 2> views{};
  for (int eye = 0; eye < 2; ++eye) views[eye].pose = moving_pose(t, eye);
  return views;
}

void expect_pose_near(const Pose& actual, const Pose& expected, double tolerance) {
  EXPECT_NEAR(glm::length(actual.position - expected.position), 0.0, tolerance);
  EXPECT_NEAR(std::abs(glm::dot(actual.orientation, expected.orientation)), 1.0, tolerance);
}

TEST(PosePredictorTest, ExactOnConstantLinearAndAngularVelocity) {
  PosePredictorConfig undamped;  // the model itself: no damping of long horizons (the default)
  undamped.damping_tau_ns = 0;
  PosePredictor predictor(undamped);
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(predictor.add(i * kFrame, moving_views(i * kFrame)));
  const int64_t last = 4 * kFrame;
  for (const int64_t horizon : {int64_t{0}, 11 * kMs, 50 * kMs, 100 * kMs}) {
    const PredictedViews p = predictor.predict(last + horizon);
    EXPECT_FALSE(p.fell_back);
    EXPECT_FALSE(p.capped);
    EXPECT_EQ(p.horizon_ns, horizon);
    for (int eye = 0; eye < 2; ++eye) expect_pose_near(p.views[eye].pose, moving_pose(last + horizon, eye), 1e-9);
  }
  EXPECT_EQ(predictor.frame_period_ns(), kFrame);
}

TEST(PosePredictorTest, HorizonIsCappedAndReported) {
  PosePredictorConfig config;
  config.max_horizon_ns = 30 * kMs;
  PosePredictor predictor(config);
  predictor.add(0, moving_views(0));
  predictor.add(kFrame, moving_views(kFrame));
  const PredictedViews p = predictor.predict(kFrame + 500 * kMs);
  EXPECT_FALSE(p.fell_back);
  EXPECT_TRUE(p.capped);
  EXPECT_EQ(p.horizon_ns, 30 * kMs);
  expect_pose_near(p.views[1].pose, moving_pose(kFrame + 30 * kMs, 1), 1e-9);
}

TEST(PosePredictorTest, TargetInThePastGivesTheNewestPose) {
  PosePredictor predictor;
  predictor.add(0, moving_views(0));
  predictor.add(kFrame, moving_views(kFrame));
  const PredictedViews p = predictor.predict(kFrame / 2);
  EXPECT_FALSE(p.fell_back);
  EXPECT_EQ(p.horizon_ns, 0);
  // Bit-exact, so that a zero horizon traces exactly what the client sent.
  EXPECT_EQ(p.views[0].pose.position, moving_pose(kFrame, 0).position);
  EXPECT_EQ(p.views[0].pose.orientation, moving_pose(kFrame, 0).orientation);
}

TEST(PosePredictorTest, ShortHistoryFallsBackToTheNewestPose) {
  PosePredictor predictor;
  EXPECT_TRUE(predictor.predict(0).fell_back);
  predictor.add(5 * kFrame, moving_views(5 * kFrame));
  const PredictedViews p = predictor.predict(5 * kFrame + 20 * kMs);
  EXPECT_TRUE(p.fell_back);
  EXPECT_EQ(p.horizon_ns, 0);
  expect_pose_near(p.views[0].pose, moving_pose(5 * kFrame, 0), 1e-12);
  EXPECT_EQ(predictor.frame_period_ns(), 0);
}

TEST(PosePredictorTest, ImplausibleMotionFallsBack) {
  PosePredictor predictor;
  predictor.add(0, moving_views(0));
  std::array<View, 2> jumped = moving_views(kFrame);
  jumped[1].pose.position.x += 2.0;  // 2 m in 11 ms: a tracking glitch, not a head
  predictor.add(kFrame, jumped);
  PredictedViews p = predictor.predict(kFrame + 50 * kMs);
  EXPECT_TRUE(p.fell_back);
  expect_pose_near(p.views[1].pose, jumped[1].pose, 1e-12);
  expect_pose_near(p.views[0].pose, jumped[0].pose, 1e-12);  // both eyes fall back together

  PosePredictor spinning;
  std::array<View, 2> a = moving_views(0), b = moving_views(kFrame);
  for (View& v : b) v.pose.orientation = glm::angleAxis(0.5, glm::dvec3(0.0, 1.0, 0.0)) * v.pose.orientation;
  spinning.add(0, a);
  spinning.add(kFrame, b);  // 0.5 rad in 11 ms = 45 rad/s
  p = spinning.predict(kFrame + 50 * kMs);
  EXPECT_TRUE(p.fell_back);
}

TEST(PosePredictorTest, NonFiniteAndOutOfOrderInputIsIgnored) {
  PosePredictor predictor;
  EXPECT_TRUE(predictor.add(0, moving_views(0)));
  EXPECT_TRUE(predictor.add(kFrame, moving_views(kFrame)));
  std::array<View, 2> bad = moving_views(2 * kFrame);
  bad[0].pose.position.y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(predictor.add(2 * kFrame, bad));
  bad = moving_views(2 * kFrame);
  bad[1].pose.orientation = glm::dquat(0.0, 0.0, 0.0, 0.0);
  EXPECT_FALSE(predictor.add(2 * kFrame, bad));
  bad = moving_views(2 * kFrame);
  bad[1].fov.angle_left = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(predictor.add(2 * kFrame, bad));
  EXPECT_FALSE(predictor.add(kFrame, moving_views(kFrame)));      // not newer
  EXPECT_FALSE(predictor.add(kFrame / 2, moving_views(kFrame)));  // older
  EXPECT_EQ(predictor.size(), 2u);
  const PredictedViews p = predictor.predict(kFrame + 40 * kMs);
  EXPECT_FALSE(p.fell_back);
  for (int eye = 0; eye < 2; ++eye) expect_pose_near(p.views[eye].pose, moving_pose(kFrame + 40 * kMs, eye), 1e-9);
}

TEST(PosePredictorTest, HistoryIsBoundedAndConfigIsChecked) {
  PosePredictorConfig config;
  config.history = 3;
  PosePredictor predictor(config);
  for (int i = 0; i < 10; ++i) predictor.add(i * kFrame, moving_views(i * kFrame));
  EXPECT_EQ(predictor.size(), 3u);
  EXPECT_EQ(predictor.newest_time_ns(), 9 * kFrame);
  config.history = 1;
  EXPECT_THROW(PosePredictor{config}, std::invalid_argument);
  config = PosePredictorConfig{};
  config.max_horizon_ns = -1;
  EXPECT_THROW(PosePredictor{config}, std::invalid_argument);
}

TEST(FrameGrid, HorizonRoundsUpToWholeClientFrames) {
  EXPECT_EQ(round_up_to_frame_grid(0, kFrame), 0);
  EXPECT_EQ(round_up_to_frame_grid(-5 * kMs, kFrame), 0);
  EXPECT_EQ(round_up_to_frame_grid(1, kFrame), kFrame);
  EXPECT_EQ(round_up_to_frame_grid(25 * kMs, kFrame), 3 * kFrame);  // 25 ms RTT: shown 3 frames later
  EXPECT_EQ(round_up_to_frame_grid(3 * kFrame, kFrame), 3 * kFrame);  // on the grid: unchanged
  EXPECT_EQ(round_up_to_frame_grid(3 * kFrame + 1, kFrame), 4 * kFrame);
  // Unknown or implausible periods leave the horizon alone.
  for (int64_t period : {int64_t{0}, int64_t{-kFrame}, kMs / 2, 101 * kMs, std::numeric_limits<int64_t>::max()}) {
    EXPECT_EQ(round_up_to_frame_grid(25 * kMs, period), 25 * kMs) << period;
  }
  // Large horizons stay exact (no overflow in the rounding).
  EXPECT_EQ(round_up_to_frame_grid(int64_t{1} << 60, 8 * kMs) % (8 * kMs), 0);
}

// A velocity window measures over a longer baseline: tracking noise of +-2 mm on a 1 m/s walk throws the
// two-pose estimate off by 0.36 m/s, the 44 ms window by a quarter of that.
TEST(PosePredictor, VelocityWindowAveragesOutTrackingNoise) {
  auto noisy = [](int i) {
    std::array<View, 2> v{};
    for (auto& e : v) e.pose.position = glm::dvec3(1.0 * i * kFrame * 1e-9 + (i % 2 ? 0.002 : -0.002), 1.6, 0.0);
    return v;
  };
  PosePredictorConfig two;
  PosePredictorConfig window;
  window.velocity_window_ns = 45'000'000;  // frames 0..4 of frame 4
  PosePredictor a(two), b(window);
  for (int i = 0; i <= 4; ++i) {
    ASSERT_TRUE(a.add(i * kFrame, noisy(i)));
    ASSERT_TRUE(b.add(i * kFrame, noisy(i)));
  }
  const int64_t target = 4 * kFrame + 100'000'000;  // 100 ms ahead
  const double truth = 1.0 * static_cast<double>(target) * 1e-9;
  const double err_two = std::fabs(a.predict(target).views[0].pose.position.x - truth);
  const double err_window = std::fabs(b.predict(target).views[0].pose.position.x - truth);
  EXPECT_GT(err_two, 0.03);
  EXPECT_LT(err_window, err_two / 3.0);
  PosePredictorConfig bad;
  bad.velocity_window_ns = -1;
  EXPECT_THROW(PosePredictor{bad}, std::invalid_argument);
}

// Damping beyond the soft horizon: a horizon up to soft_horizon_ns is used as asked; beyond it the extra time
// counts less and less (soft + tau * (1 - exp(-(h - soft) / tau))), never more than max_horizon_ns.
TEST(PosePredictor, HorizonsBeyondTheSoftHorizonAreDamped) {
  PosePredictorConfig config;
  config.soft_horizon_ns = 50 * kMs;
  config.damping_tau_ns = 150 * kMs;
  config.max_horizon_ns = 250 * kMs;
  PosePredictor predictor(config);
  predictor.add(0, moving_views(0));
  predictor.add(kFrame, moving_views(kFrame));
  const auto used = [&](int64_t h) { return predictor.predict(kFrame + h).horizon_ns; };
  EXPECT_EQ(used(30 * kMs), 30 * kMs);
  EXPECT_EQ(used(50 * kMs), 50 * kMs);
  const double expected_111 = 50e6 + 150e6 * (1.0 - std::exp(-61.0 / 150.0));
  EXPECT_NEAR(static_cast<double>(used(111 * kMs)), expected_111, 1.0);
  int64_t previous = 0;
  for (int64_t h = 0; h <= 2000 * kMs; h += 10 * kMs) {  // monotonic, and below the soft horizon + tau
    EXPECT_GE(used(h), previous);
    previous = used(h);
    EXPECT_LT(used(h), 200 * kMs);
  }
  config.damping_tau_ns = -1;
  EXPECT_THROW(PosePredictor{config}, std::invalid_argument);
}

// Constant linear and angular acceleration about a fixed axis: the quadratic fit is exact, the velocity model
// is not; with fewer than three poses in the window the quadratic model falls back to the velocity model.
TEST(PosePredictor, QuadraticFitIsExactOnConstantAcceleration) {
  const glm::dvec3 accel{2.0, -1.0, 0.5};  // m/s^2
  const double alpha = 6.0;                // rad/s^2
  const auto pose_at = [&](int64_t t_ns) {
    const double t = static_cast<double>(t_ns) * 1e-9;
    Pose p;
    p.position = glm::dvec3(0.2, 1.5, -1.0) + kVelocity * t + 0.5 * accel * t * t;
    p.orientation = glm::angleAxis(kAngularSpeed * t + 0.5 * alpha * t * t, kAxis);
    return p;
  };
  PosePredictorConfig config;
  config.quadratic_window_ns = 60 * kMs;
  PosePredictor quadratic(config);
  PosePredictor velocity;
  for (int i = 0; i < 8; ++i) {
    std::array<View, 2> views{};
    for (View& v : views) v.pose = pose_at(i * kFrame);
    quadratic.add(i * kFrame, views);
    velocity.add(i * kFrame, views);
  }
  const int64_t target = 7 * kFrame + 80 * kMs;
  const PredictedViews q = quadratic.predict(target);
  ASSERT_FALSE(q.fell_back);
  expect_pose_near(q.views[0].pose, pose_at(target), 1e-9);
  const PredictedViews v = velocity.predict(target);
  EXPECT_GT(glm::length(v.views[0].pose.position - pose_at(target).position), 1e-3);

  PosePredictorConfig narrow;
  narrow.quadratic_window_ns = kFrame;  // two poses in the window: the velocity model
  PosePredictor fallback(narrow);
  for (int i = 0; i < 8; ++i) {
    std::array<View, 2> views{};
    for (View& view : views) view.pose = pose_at(i * kFrame);
    fallback.add(i * kFrame, views);
  }
  const PredictedViews f = fallback.predict(target);
  EXPECT_EQ(f.views[0].pose.position, v.views[0].pose.position);
  PosePredictorConfig bad;
  bad.quadratic_window_ns = -1;
  EXPECT_THROW(PosePredictor{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace dhr::server
