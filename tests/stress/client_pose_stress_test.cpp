// The client's pose input under a hostile stream (xrclient/pose/pose_guard.hpp): a long head motion in
// which every 13th frame carries a NaN / Inf / zero quaternion, a huge translation or a broken FOV in one
// eye. Every bad frame is rejected and counted, the frame reuses the last valid views, and no bad value
// ever comes out.
#include "pose/pose_guard.hpp"
#include "stress_support.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <limits>

namespace dhr::stress {
namespace {

void corrupt(View& view, uint64_t kind) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN(), kInf = std::numeric_limits<double>::infinity();
  switch (kind % 7) {
    case 0: view.pose.position.x = kNaN; break;
    case 1: view.pose.position.y = -kInf; break;
    case 2: view.pose.orientation = glm::dquat(kNaN, 0.0, 0.0, 0.0); break;
    case 3: view.pose.orientation = glm::dquat(0.0, 0.0, 0.0, 0.0); break;
    case 4: view.pose.position.z = 5e6; break;
    case 5: view.fov.angle_left = std::numeric_limits<float>::infinity(); break;
    default: view.fov.angle_up = -0.1f; view.fov.angle_down = 0.2f; break;  // inverted
  }
}

TEST(StressPoses, ClientPoseGuardRejectsCountsAndNeverPropagates) {
  const uint64_t frames = pick<uint64_t>(200'000, 2'000'000);
  std::array<View, 2> start{};
  start[0].pose.position = {-0.032, 1.6, 0.0};
  start[1].pose.position = {0.032, 1.6, 0.0};
  client::PoseGuard guard(start);
  std::array<View, 2> previous = start;
  uint64_t bad = 0, leaked = 0, not_reused = 0;
  for (uint64_t n = 0; n < frames; ++n) {
    const double t = double(n) / 90.0;
    std::array<View, 2> views;
    for (int e = 0; e < 2; ++e) {
      views[e].pose.position = {0.064 * (e - 0.5) + 0.3 * std::sin(t), 1.6 + 0.05 * std::sin(3 * t), 0.2 * std::cos(t)};
      views[e].pose.orientation = glm::angleAxis(0.8 * std::sin(0.5 * t), glm::dvec3(0.0, 1.0, 0.0)) *
                                  glm::dquat(1.0, 1e-3 * std::sin(t), 0.0, 0.0);  // slightly off unit
    }
    const bool inject = n % 13 == 5;
    if (inject) {
      corrupt(views[n % 2], n / 13);
      ++bad;
    }
    const bool reused = guard.filter(n, views);
    EXPECT_EQ(reused, inject) << "frame " << n;
    for (const View& v : views) {
      if (client::PoseGuard::check(v) || std::fabs(glm::length(v.pose.orientation) - 1.0) > 1e-12) ++leaked;
    }
    if (reused && !(views[0].pose.position == previous[0].pose.position &&
                    views[1].pose.orientation == previous[1].pose.orientation)) {
      ++not_reused;
    }
    previous = views;
  }
  report("client_pose_guard", "bad_views_passed_on", double(leaked), 0.0);
  std::printf("[stress] client_pose_guard: %llu frames, %llu injected, %llu rejected\n",
              static_cast<unsigned long long>(frames), static_cast<unsigned long long>(bad),
              static_cast<unsigned long long>(guard.rejected()));
  EXPECT_EQ(leaked, 0u);
  EXPECT_EQ(not_reused, 0u);
  EXPECT_EQ(guard.rejected(), bad);
}

}  // namespace
}  // namespace dhr::stress
