// FramePlanner: per frame, which visibility each eye uses, which view it renders and submits, the traced
// camera, p and x, and the response bookkeeping, for every schedule.
#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "plan/frame_planner.hpp"

namespace dhr::client {
namespace {

const TracedFormat kFormat{Extent{40, 30}, GuardBand{2, 1}};

FramePose pose_at(uint64_t frame) {
  FramePose p{frame, static_cast<int64_t>(frame) * 1000, {}};
  for (uint32_t e = 0; e < 2; ++e) p.views[e].pose.position = glm::dvec3(0.01 * static_cast<double>(frame), e, 0);
  return p;
}

VisibilityFrame received(uint64_t frame, uint32_t eye, bool complete = true) {
  VisibilityFrame v;
  v.frame_number = frame;
  v.eye = eye == 0 ? Eye::kLeft : Eye::kRight;
  v.view = pose_at(frame).views[eye];
  v.buffer = VisibilityBuffer::create(kFormat.buffer().width, kFormat.buffer().height, 3);
  v.row_valid.assign(v.buffer.height, complete ? 1 : 0);
  v.complete = complete;
  return v;
}

// Plans frames 0..n-1 (records their poses) and returns the plan of frame n.
FramePlan plan_through(FramePlanner& planner, uint64_t n, const ResponseLookup& lookup = {}) {
  for (uint64_t f = 0; f < n; ++f) planner.record(pose_at(f));
  return planner.plan(pose_at(n), kFormat, lookup);
}

TEST(FramePlannerTest, WithoutVisibilityEveryEyeShowsFrameNWithNothingToWarp) {
  FramePlanner planner(PlannerSettings{});
  const FramePlan plan = planner.plan(pose_at(5), kFormat);
  for (uint32_t e = 0; e < 2; ++e) {
    EXPECT_FALSE(plan.eyes[e].has_visibility);
    EXPECT_EQ(plan.eyes[e].visibility.buffer, nullptr);
    EXPECT_EQ(plan.eyes[e].display_frame, 5u);
    EXPECT_EQ(plan.eyes[e].view.pose.position, pose_at(5).views[e].pose.position);
    EXPECT_EQ(plan.eyes[e].visibility.traced.extent, kFormat.buffer());
  }
  EXPECT_FALSE(plan.response_ms.has_value());
}

TEST(FramePlannerTest, PaperRendersFrameNMinusPPlusXAndWarpsFromTheTracedView) {
  FramePlanner planner(PlannerSettings{Schedule::kPaper, 3, 64});
  ASSERT_TRUE(planner.offer(0, received(12, 0)));
  ASSERT_TRUE(planner.offer(1, received(12, 1)));
  const FramePlan plan = plan_through(planner, 20);  // p = 8, x = 3: frame 15
  for (uint32_t e = 0; e < 2; ++e) {
    const EyePlan& p = plan.eyes[e];
    EXPECT_TRUE(p.has_visibility);
    EXPECT_EQ(p.age, 8u);
    EXPECT_EQ(p.predicted, 3u);
    EXPECT_EQ(p.display_frame, 15u);
    EXPECT_EQ(p.view.pose.position, pose_at(15).views[e].pose.position);  // rendered and submitted
    const Camera traced = kFormat.camera(pose_at(12).views[e]);
    EXPECT_EQ(p.visibility.traced.T_world_eye.position, traced.T_world_eye.position);
    EXPECT_EQ(p.visibility.traced.extent, traced.extent);
    EXPECT_EQ(p.visibility.buffer, &planner.held(e)->buffer);
    EXPECT_TRUE(p.visibility.row_valid.empty());  // complete
    EXPECT_EQ(p.visibility_age_ns, 8000);
  }
}

TEST(FramePlannerTest, NewestWarpsOverAllFramesAndStaleDoesNotWarp) {
  FramePlanner newest(PlannerSettings{Schedule::kNewest, 3, 64});
  newest.offer(0, received(12, 0));
  const EyePlan n = plan_through(newest, 20).eyes[0];
  EXPECT_EQ(n.display_frame, 20u);
  EXPECT_EQ(n.predicted, 8u);
  EXPECT_EQ(n.visibility.traced.T_world_eye.position, pose_at(12).views[0].pose.position);

  FramePlanner stale(PlannerSettings{Schedule::kStale, 3, 64});
  stale.offer(0, received(12, 0));
  const EyePlan s = plan_through(stale, 20).eyes[0];
  EXPECT_EQ(s.display_frame, 20u);
  EXPECT_EQ(s.age, 8u);
  EXPECT_EQ(s.predicted, 0u);
  // The old bits as if traced for the displayed view.
  EXPECT_EQ(s.visibility.traced.T_world_eye.position, pose_at(20).views[0].pose.position);
}

TEST(FramePlannerTest, PaperFallsBackToFrameNWhenTheShownFrameLeftTheHistory) {
  FramePlanner planner(PlannerSettings{Schedule::kPaper, 3, 4});  // a 4-frame ring
  planner.offer(0, received(2, 0));
  const EyePlan p = plan_through(planner, 20).eyes[0];  // frame 5 is long gone
  EXPECT_EQ(p.display_frame, 20u);
  EXPECT_EQ(p.view.pose.position, pose_at(20).views[0].pose.position);
  EXPECT_FALSE(p.visibility_age_ns.has_value());
}

TEST(FramePlannerTest, OlderFramesNeverReplaceNewerOnesAndPartialFramesCarryTheirRows) {
  FramePlanner planner(PlannerSettings{});
  EXPECT_TRUE(planner.offer(0, received(10, 0, false)));
  EXPECT_FALSE(planner.offer(0, received(9, 0)));
  EXPECT_EQ(planner.held(0)->frame_number, 10u);
  const EyePlan p = planner.plan(pose_at(11), kFormat).eyes[0];
  EXPECT_FALSE(p.complete);
  EXPECT_EQ(p.visibility.row_valid.size(), kFormat.buffer().height);
  EXPECT_TRUE(planner.offer(0, received(10, 0, true)));  // the same frame, now whole
  EXPECT_TRUE(planner.plan(pose_at(12), kFormat).eyes[0].complete);
}

TEST(FramePlannerTest, ANewerFrameMovesTheHeldOneToOlderWithItsRowsAndTracedCamera) {
  FramePlanner planner(PlannerSettings{});
  EXPECT_EQ(plan_through(planner, 3).eyes[0].older.buffer, nullptr);  // nothing held
  ASSERT_TRUE(planner.offer(0, received(4, 0, false)));
  EXPECT_EQ(plan_through(planner, 5).eyes[0].older.buffer, nullptr);  // one frame held: no previous
  ASSERT_TRUE(planner.offer(0, received(4, 0, true)));                // the same frame, now whole
  EXPECT_FALSE(planner.previous(0).has_value());
  ASSERT_TRUE(planner.offer(0, received(6, 0, false)));
  ASSERT_TRUE(planner.offer(0, received(7, 0)));
  const FramePlan plan = plan_through(planner, 8);
  const EyePlan& p = plan.eyes[0];
  EXPECT_EQ(p.visibility_frame, 7u);
  ASSERT_NE(p.older.buffer, nullptr);
  EXPECT_EQ(p.older.buffer, &planner.previous(0)->buffer);
  EXPECT_EQ(p.older_frame, 6u);
  EXPECT_FALSE(p.older_complete);
  EXPECT_EQ(p.older.row_valid.size(), kFormat.buffer().height);  // its missing rows travel with it
  EXPECT_EQ(p.older.traced.T_world_eye.position, kFormat.camera(pose_at(6).views[0]).T_world_eye.position);
  EXPECT_EQ(plan.eyes[1].older.buffer, nullptr);  // per eye
  // An older frame offered later is ignored and moves nothing.
  EXPECT_FALSE(planner.offer(0, received(5, 0)));
  EXPECT_EQ(planner.previous(0)->frame_number, 6u);
  // kStale does not warp, so it has no use for an older buffer.
  FramePlanner stale(PlannerSettings{Schedule::kStale, 3, 64});
  stale.offer(0, received(2, 0));
  stale.offer(0, received(3, 0));
  EXPECT_EQ(plan_through(stale, 5).eyes[0].older.buffer, nullptr);
}

TEST(FramePlannerTest, WithoutAFormatHeldVisibilityIsNotUsed) {
  FramePlanner planner(PlannerSettings{});
  planner.offer(0, received(3, 0));
  const EyePlan p = planner.plan(pose_at(4), std::nullopt).eyes[0];
  EXPECT_FALSE(p.has_visibility);
  EXPECT_EQ(p.visibility.buffer, nullptr);
}

TEST(FramePlannerTest, FirstUseAndResponseTimesAreCountedOncePerVisibilityFrame) {
  FramePlanner planner(PlannerSettings{});
  std::vector<uint64_t> asked;
  const ResponseLookup lookup = [&asked](uint64_t f) -> std::optional<int64_t> {
    asked.push_back(f);
    if (f == 7) return std::nullopt;  // not known (yet)
    return static_cast<int64_t>(f) * 1'000'000;
  };
  planner.offer(0, received(5, 0));
  planner.offer(1, received(5, 1));
  FramePlan plan = plan_through(planner, 8, lookup);
  EXPECT_TRUE(plan.eyes[0].first_use && plan.eyes[1].first_use);
  ASSERT_TRUE(plan.response_ms.has_value());
  EXPECT_DOUBLE_EQ(*plan.response_ms, 5.0);
  EXPECT_EQ(asked, (std::vector<uint64_t>{5}));  // the right eye's frame 5 is not measured twice

  plan = planner.plan(pose_at(9), kFormat, lookup);  // nothing new
  EXPECT_FALSE(plan.eyes[0].first_use);
  EXPECT_FALSE(plan.response_ms.has_value());

  planner.offer(0, received(7, 0));  // unknown response: asked, not counted, asked again when re-offered
  plan = planner.plan(pose_at(10), kFormat, lookup);
  EXPECT_TRUE(plan.eyes[0].first_use);
  EXPECT_FALSE(plan.response_ms.has_value());
  planner.offer(0, received(6, 0));  // older than held: ignored, never measured
  planner.offer(1, received(8, 1));
  plan = planner.plan(pose_at(11), kFormat, lookup);
  ASSERT_TRUE(plan.response_ms.has_value());
  EXPECT_DOUBLE_EQ(*plan.response_ms, 8.0);
  EXPECT_EQ(asked, (std::vector<uint64_t>{5, 7, 8}));
}

}  // namespace
}  // namespace dhr::client
