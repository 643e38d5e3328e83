// The client application's pure parts: schedule decisions, the view history ring, the pose guard, the trace
// source's virtual clock.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "plan/schedule.hpp"
#include "plan/view_history.hpp"
#include "pose/pose_guard.hpp"
#include "pose/trace_pose_source.hpp"

namespace dhr::client {
namespace {

TEST(ClientScheduleTest, PaperShowsFrameNMinusPPlusX) {
  // n = 20, visibility of frame 12: p = 8; x_max 3 -> show frame 15, warping 3 frames.
  ScheduleDecision d = decide_schedule(Schedule::kPaper, 3, 20, 12);
  EXPECT_EQ(d.age, 8u);
  EXPECT_EQ(d.display_frame, 15u);
  EXPECT_EQ(d.predicted, 3u);
  // p <= x_max: the newest frame.
  d = decide_schedule(Schedule::kPaper, 3, 20, 18);
  EXPECT_EQ(d.display_frame, 20u);
  EXPECT_EQ(d.predicted, 2u);
  d = decide_schedule(Schedule::kNewest, 3, 20, 12);
  EXPECT_EQ(d.display_frame, 20u);
  EXPECT_EQ(d.predicted, 8u);
  d = decide_schedule(Schedule::kPaper, 3, 20, std::nullopt);
  EXPECT_EQ(d.display_frame, 20u);
  EXPECT_EQ(d.age, 0u);
  d = decide_schedule(Schedule::kPaper, 3, 20, 25);  // a frame from the future counts as n
  EXPECT_EQ(d.display_frame, 20u);
  d = decide_schedule(Schedule::kStale, 3, 20, 12);  // no warp: frame n, the bits as they are
  EXPECT_EQ(d.display_frame, 20u);
  EXPECT_EQ(d.age, 8u);
  EXPECT_EQ(d.predicted, 0u);
  EXPECT_EQ(parse_schedule("paper"), Schedule::kPaper);
  EXPECT_EQ(parse_schedule("stale"), Schedule::kStale);
  EXPECT_FALSE(parse_schedule("fast").has_value());
}

TEST(ClientViewHistoryTest, FindsFramesStillInTheRing) {
  ViewHistory history(4);
  FramePose pose;
  for (uint64_t f = 0; f < 10; ++f) {
    pose.frame = f;
    pose.display_time_ns = static_cast<int64_t>(f) * 100;
    pose.views[0].pose.position.x = static_cast<double>(f);
    history.record(pose);
  }
  ASSERT_NE(history.find(9), nullptr);
  EXPECT_EQ(history.find(7)->views[0].pose.position.x, 7.0);
  EXPECT_EQ(history.find(6)->display_time_ns, 600);
  EXPECT_EQ(history.find(5), nullptr);  // overwritten by 9
  EXPECT_EQ(history.find(11), nullptr);
}

TEST(ClientPoseGuardTest, RejectsNonFiniteAndReusesLastValid) {
  std::array<View, 2> fallback{};
  fallback[0].pose.position = {0.0, 1.6, 0.0};
  PoseGuard guard(fallback);
  std::array<View, 2> good{};
  good[0].pose.position = {1.0, 1.5, 0.0};
  good[1].pose.orientation = glm::dquat(2.0, 0.0, 0.0, 0.0);  // not unit: renormalized
  EXPECT_FALSE(guard.filter(0, good));
  EXPECT_DOUBLE_EQ(good[1].pose.orientation.w, 1.0);
  std::array<View, 2> bad = good;
  bad[1].pose.position.y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(guard.filter(1, bad));
  EXPECT_EQ(bad[0].pose.position.x, 1.0);
  EXPECT_TRUE(std::isfinite(bad[1].pose.position.y));
  std::array<View, 2> bad_fov = good;
  bad_fov[0].fov.angle_left = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(guard.filter(2, bad_fov));
  std::array<View, 2> zero_q = good;
  zero_q[0].pose.orientation = glm::dquat(0.0, 0.0, 0.0, 0.0);
  EXPECT_TRUE(guard.filter(3, zero_q));
  EXPECT_EQ(guard.rejected(), 3u);
  // The very first sample invalid: the fallback is shown.
  PoseGuard fresh(fallback);
  std::array<View, 2> nan_first = good;
  nan_first[0].pose.position.z = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(fresh.filter(0, nan_first));
  EXPECT_EQ(nan_first[0].pose.position.y, 1.6);
}

TEST(ClientTracePoseSourceTest, PlaysAtNinetyHertzUntilTheTraceEnds) {
  PoseTrace trace;
  for (int i = 0; i <= 10; ++i) {
    TraceSample s;
    s.time = 5.0 + 0.01 * i;  // 0.1 s
    s.head.position = {0.01 * i, 0.0, 0.0};
    trace.samples.push_back(s);
  }
  TracePoseSource source(trace, EyeModel{}, TracePlacement{}, "test");
  EXPECT_EQ(source.frame_count(), 10u);  // 0, 1/90, ..., 9/90 <= 0.1 s
  FramePose sample;
  uint64_t frames = 0;
  while (source.next(sample)) {
    EXPECT_EQ(sample.frame, frames);
    EXPECT_EQ(sample.display_time_ns, static_cast<int64_t>(frames) * kVirtualFramePeriodNs);
    ++frames;
  }
  EXPECT_EQ(frames, 10u);
  EXPECT_THROW(TracePoseSource::load("/nonexistent/trace.csv"), std::runtime_error);
}

}  // namespace
}  // namespace dhr::client
