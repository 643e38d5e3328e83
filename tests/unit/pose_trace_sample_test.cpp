// Sampling a trace: linear position, shortest-path slerp, clamped ends, resampling and truncation.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <numbers>

#include "traces/pose_trace.hpp"

namespace {

constexpr double kPi = std::numbers::pi;

glm::dquat yaw(double radians) { return glm::angleAxis(radians, glm::dvec3(0.0, 1.0, 0.0)); }

// Angle of the rotation between two unit quaternions, accurate for tiny angles (acos is not).
double angle_between(const glm::dquat& a, glm::dquat b) {
  if (glm::dot(a, b) < 0.0) b = -b;
  return 4.0 * std::atan2(glm::length(b - a), glm::length(b + a));
}

dhr::TraceSample make(double t, glm::dvec3 p, glm::dquat q) {
  dhr::TraceSample s;
  s.time = t;
  s.head.position = p;
  s.head.orientation = q;
  return s;
}

dhr::PoseTrace two_samples(const glm::dquat& a, const glm::dquat& b) {
  dhr::PoseTrace trace;
  trace.samples = {make(1.0, {0.0, 1.0, 0.0}, a), make(3.0, {2.0, 1.0, -4.0}, b)};
  return trace;
}

TEST(Slerp, MidpointOfKnownRotations) {
  const dhr::PoseTrace trace = two_samples(yaw(0.0), yaw(kPi / 2.0));
  const dhr::TraceSample mid = trace.sample(2.0);
  EXPECT_EQ(mid.time, 2.0);
  EXPECT_NEAR(angle_between(mid.head.orientation, yaw(kPi / 4.0)), 0.0, 1e-12);
  EXPECT_NEAR(glm::length(mid.head.position - glm::dvec3(1.0, 1.0, -2.0)), 0.0, 1e-15);
  const dhr::TraceSample quarter = trace.sample(1.5);
  EXPECT_NEAR(angle_between(quarter.head.orientation, yaw(kPi / 8.0)), 0.0, 1e-12);
  // A rotation about another axis: 0 -> 120 degrees about x, a third of the way is 40 degrees.
  const glm::dvec3 x(1.0, 0.0, 0.0);
  const dhr::PoseTrace pitch = two_samples(glm::dquat(1.0, 0.0, 0.0, 0.0), glm::angleAxis(2.0 * kPi / 3.0, x));
  EXPECT_NEAR(angle_between(pitch.sample(1.0 + 2.0 / 3.0).head.orientation, glm::angleAxis(2.0 * kPi / 9.0, x)), 0.0,
              1e-12);
}

TEST(Slerp, TakesTheShortestPath) {
  // 170 degrees -> -170 degrees of yaw: the short way crosses 180, not 0; and -q counts as q.
  const glm::dquat a = yaw(170.0 * kPi / 180.0);
  const glm::dquat b = -yaw(-170.0 * kPi / 180.0);
  const dhr::PoseTrace trace = two_samples(a, b);
  EXPECT_NEAR(angle_between(trace.sample(2.0).head.orientation, yaw(kPi)), 0.0, 1e-12);
  EXPECT_NEAR(angle_between(dhr::slerp_shortest(a, b, 0.25), yaw(175.0 * kPi / 180.0)), 0.0, 1e-12);
  // Identical and nearly identical rotations stay unit and exact.
  const glm::dquat q = glm::normalize(glm::dquat(0.3, -0.2, 0.9, 0.1));
  const glm::dquat s = dhr::slerp_shortest(q, q, 0.37);
  EXPECT_NEAR(glm::length(s), 1.0, 1e-15);
  EXPECT_NEAR(angle_between(s, q), 0.0, 1e-15);
  const glm::dquat tiny = q * glm::angleAxis(1e-9, glm::dvec3(0.0, 0.0, 1.0));
  EXPECT_NEAR(angle_between(dhr::slerp_shortest(q, tiny, 0.5), q * glm::angleAxis(0.5e-9, glm::dvec3(0, 0, 1))),
              0.0, 1e-15);
}

TEST(Sample, ClampsAtTheEndsAndHitsRowsExactly) {
  const dhr::PoseTrace trace = two_samples(yaw(0.1), yaw(0.7));
  EXPECT_EQ(trace.sample(-100.0).head.position, trace.samples[0].head.position);
  EXPECT_EQ(trace.sample(std::nan("")).head.position, trace.samples[0].head.position);
  EXPECT_EQ(trace.sample(1e9).head.position, trace.samples[1].head.position);
  EXPECT_EQ(trace.sample(1e9).head.orientation, trace.samples[1].head.orientation);
  EXPECT_EQ(trace.sample(1.0).head.orientation, trace.samples[0].head.orientation);
  EXPECT_EQ(trace.sample(3.0).head.position, trace.samples[1].head.position);
  dhr::PoseTrace empty;
  EXPECT_THROW((void)empty.sample(0.0), std::logic_error);
}

TEST(Sample, RepeatedTimestampsAreHandled) {
  dhr::PoseTrace trace;
  trace.samples = {make(0.0, {0, 0, 0}, yaw(0.0)), make(1.0, {1, 0, 0}, yaw(0.2)), make(1.0, {5, 0, 0}, yaw(0.4)),
                   make(2.0, {6, 0, 0}, yaw(0.6))};
  EXPECT_NEAR(trace.sample(0.5).head.position.x, 0.5, 1e-15);
  EXPECT_EQ(trace.sample(1.0).head.position.x, 5.0);  // the later of the two rows at t = 1
  EXPECT_NEAR(trace.sample(1.5).head.position.x, 5.5, 1e-15);
}

TEST(Sample, InterpolatesEyesAndFov) {
  dhr::PoseTrace trace = two_samples(yaw(0.0), yaw(0.0));
  trace.has_eye_poses = true;
  trace.has_fov = true;
  trace.samples[0].eye[0].position = {-0.03, 0.0, 0.0};
  trace.samples[1].eye[0].position = {-0.05, 0.0, 0.0};
  trace.samples[0].fov[1].angle_right = 0.6f;
  trace.samples[1].fov[1].angle_right = 0.8f;
  const dhr::TraceSample mid = trace.sample(2.0);
  EXPECT_NEAR(mid.eye[0].position.x, -0.04, 1e-15);
  EXPECT_NEAR(mid.fov[1].angle_right, 0.7f, 1e-6f);
}

TEST(Resample, FixedRateFromTheStart) {
  dhr::PoseTrace trace;
  for (int i = 0; i <= 10; ++i) {
    trace.samples.push_back(make(2.0 + 0.1 * i, {0.1 * i, 0, 0}, yaw(0.05 * i)));
  }
  trace.comments = {"c"};
  const dhr::PoseTrace at90 = dhr::resample_trace(trace, 90.0);
  ASSERT_EQ(at90.samples.size(), 91u);  // 0 .. 1 s inclusive
  EXPECT_EQ(at90.comments, trace.comments);
  for (std::size_t i = 0; i < at90.samples.size(); ++i) {
    const double t = 2.0 + static_cast<double>(i) / 90.0;
    ASSERT_EQ(at90.samples[i].time, t);
    ASSERT_NEAR(at90.samples[i].head.position.x, t - 2.0, 1e-12);
    ASSERT_NEAR(angle_between(at90.samples[i].head.orientation, yaw(0.5 * (t - 2.0))), 0.0, 1e-9);
  }
  EXPECT_EQ(dhr::resample_trace(trace, 0.5).samples.size(), 1u);
  EXPECT_THROW(dhr::resample_trace(trace, 0.0), std::invalid_argument);
  EXPECT_THROW(dhr::resample_trace(trace, -1.0), std::invalid_argument);
  EXPECT_THROW(dhr::resample_trace(dhr::PoseTrace{}, 90.0), std::invalid_argument);

  const dhr::PoseTrace first = dhr::truncate_trace(trace, 0.35);
  ASSERT_EQ(first.samples.size(), 4u);
  EXPECT_EQ(dhr::truncate_trace(trace, 0.0).samples.size(), 1u);
}

}  // namespace
