// App-moved nodes (scene/node_overrides.hpp): the rule for a node's local transform at a scene time given the
// transforms an application sent (hold from each stamp, extrapolate beyond the newest for a bounded horizon, then
// hold), what add() accepts, and that node_world_at, light_at, scene_at and SceneMotion apply it. On the test
// animated scene (node 1 moves 4 m along +x and turns 90 degrees over a 2 s loop; node 0 is static).
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <vector>

#include "scene/node_overrides.hpp"
#include "scene/scene_at.hpp"
#include "scene/scene_motion.hpp"
#include "test_animated_scene.hpp"

namespace dhr {
namespace {

using test::kMovingNode;
using test::kStaticNode;

constexpr int64_t kMs = 1'000'000;

Trs at_x(double x) { return Trs{glm::dvec3(x, 0.0, 2.0), glm::dquat(1.0, 0.0, 0.0, 0.0), glm::dvec3(1.0)}; }

glm::dvec3 origin_of(const glm::dmat4& m) { return glm::dvec3(m[3]); }

TEST(NodeOverrides, BeforeTheFirstTransformTheAnimationPlays) {
  const Scene s = test::animated_scene();
  NodeOverrides o;
  ASSERT_EQ(o.add(s.animation, kMovingNode, 1000 * kMs, at_x(-3.0)), NodeTransformVerdict::kAccepted);
  for (const double t : {0.0, 0.5, 0.999}) {
    EXPECT_FALSE(o.trs_at(kMovingNode, t).has_value()) << t;
    EXPECT_EQ(node_world_at(s, kMovingNode, t, &o), node_world_at(s, kMovingNode, t)) << t;
  }
}

TEST(NodeOverrides, FromItsStampATransformReplacesTheAnimationAndIsHeld) {
  const Scene s = test::animated_scene();
  NodeOverrides o;
  ASSERT_EQ(o.add(s.animation, kMovingNode, 500 * kMs, at_x(-3.0)), NodeTransformVerdict::kAccepted);
  // One transform: held for ever (no extrapolation from a single one), whatever the animation does.
  for (const double t : {0.5, 0.75, 1.5, 10.0}) {
    const glm::dmat4 world = node_world_at(s, kMovingNode, t, &o);
    EXPECT_EQ(world, trs_matrix(at_x(-3.0))) << t;  // a root node: world = local
    EXPECT_NE(world, node_world_at(s, kMovingNode, t)) << t;
  }
  // A second transform: the first holds until its stamp.
  ASSERT_EQ(o.add(s.animation, kMovingNode, 900 * kMs, at_x(-2.0)), NodeTransformVerdict::kAccepted);
  EXPECT_EQ(o.trs_at(kMovingNode, 0.899)->translation.x, -3.0);
  EXPECT_EQ(o.trs_at(kMovingNode, 0.9)->translation.x, -2.0);
}

TEST(NodeOverrides, BeyondTheNewestItExtrapolatesForTheHorizonThenHolds) {
  const Scene s = test::animated_scene();
  NodeOverrides o;
  Trs a = at_x(0.0), b = at_x(1.0);  // 1 m in 0.5 s: 2 m/s along x
  a.scale = glm::dvec3(1.0);
  b.scale = glm::dvec3(1.5);  // +1 per second
  a.rotation = glm::angleAxis(0.0, glm::dvec3(0.0, 1.0, 0.0));
  b.rotation = glm::angleAxis(0.2, glm::dvec3(0.0, 1.0, 0.0));  // 0.4 rad/s about +y
  ASSERT_EQ(o.add(s.animation, kMovingNode, 1000 * kMs, a), NodeTransformVerdict::kAccepted);
  ASSERT_EQ(o.add(s.animation, kMovingNode, 1500 * kMs, b), NodeTransformVerdict::kAccepted);
  const Trs ahead = o.trs_at(kMovingNode, 1.6).value();  // 0.1 s past the newest
  EXPECT_NEAR(ahead.translation.x, 1.2, 1e-12);
  EXPECT_NEAR(ahead.scale.x, 1.6, 1e-12);
  EXPECT_NEAR(glm::angle(ahead.rotation), 0.24, 1e-9);
  // Past the horizon (0.25 s): held where the horizon ends.
  const double horizon = node_stamp_seconds(kNodeExtrapolationHorizonNs);
  const Trs end = o.trs_at(kMovingNode, 1.5 + horizon).value();
  EXPECT_NEAR(end.translation.x, 1.0 + 2.0 * horizon, 1e-12);
  for (const double t : {1.8, 3.0, 100.0}) EXPECT_EQ(o.trs_at(kMovingNode, t), end) << t;
  // Between the two stamps the older is held: no interpolation.
  EXPECT_EQ(o.trs_at(kMovingNode, 1.25), a);
}

TEST(NodeOverrides, AnExtrapolatedScaleStaysPositive) {
  const Scene s = test::animated_scene();
  NodeOverrides o;
  Trs a = at_x(0.0), b = at_x(0.0);
  a.scale = glm::dvec3(1.0);
  b.scale = glm::dvec3(0.1);  // shrinking by 9 per second: linear would cross 0 within the horizon
  ASSERT_EQ(o.add(s.animation, kMovingNode, 0, a), NodeTransformVerdict::kAccepted);
  ASSERT_EQ(o.add(s.animation, kMovingNode, 100 * kMs, b), NodeTransformVerdict::kAccepted);
  const Trs later = o.trs_at(kMovingNode, 0.3).value();
  EXPECT_GT(later.scale.x, 0.0);
  EXPECT_TRUE(valid_trs(later));
}

TEST(NodeOverrides, UnknownOutOfOrderLateAndInvalidTransformsAreRefused) {
  const Scene s = test::animated_scene();
  NodeOverrides o;
  EXPECT_EQ(o.add(s.animation, kStaticNode, 0, at_x(0.0)), NodeTransformVerdict::kUnknownNode);
  EXPECT_EQ(o.add(s.animation, 77, 0, at_x(0.0)), NodeTransformVerdict::kUnknownNode);
  ASSERT_EQ(o.add(s.animation, kMovingNode, 200 * kMs, at_x(0.0)), NodeTransformVerdict::kAccepted);
  EXPECT_EQ(o.add(s.animation, kMovingNode, 200 * kMs, at_x(1.0)), NodeTransformVerdict::kOutOfOrder);
  EXPECT_EQ(o.add(s.animation, kMovingNode, 100 * kMs, at_x(1.0)), NodeTransformVerdict::kOutOfOrder);
  EXPECT_EQ(o.add(s.animation, kMovingNode, 300 * kMs, at_x(1.0), 400 * kMs), NodeTransformVerdict::kLate);
  Trs bad = at_x(1.0);
  bad.scale.y = 0.0;
  EXPECT_EQ(o.add(s.animation, kMovingNode, 300 * kMs, bad), NodeTransformVerdict::kInvalid);
  bad = at_x(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(o.add(s.animation, kMovingNode, 300 * kMs, bad), NodeTransformVerdict::kInvalid);
  bad = at_x(1.0);
  bad.rotation = glm::dquat(2.0, 0.0, 0.0, 0.0);
  EXPECT_EQ(o.add(s.animation, kMovingNode, 300 * kMs, bad), NodeTransformVerdict::kInvalid);
  EXPECT_EQ(o.add(s.animation, kMovingNode, -1, at_x(1.0)), NodeTransformVerdict::kOutOfOrder);  // older anyway
  NodeOverrides fresh;
  EXPECT_EQ(fresh.add(s.animation, kMovingNode, -1, at_x(1.0)), NodeTransformVerdict::kInvalid);
  // Only the accepted one counts.
  EXPECT_EQ(o.revision(), 1u);
  EXPECT_EQ(o.newest(kMovingNode)->scene_time_ns, 200 * kMs);
}

TEST(NodeOverrides, TheHistoryKeepsTheNewestTransforms) {
  const Scene s = test::animated_scene();
  NodeOverrides o;
  for (int i = 0; i < 20; ++i)
    ASSERT_EQ(o.add(s.animation, kMovingNode, i * 100 * kMs, at_x(i)), NodeTransformVerdict::kAccepted);
  EXPECT_NEAR(o.trs_at(kMovingNode, 1.95)->translation.x, 19.5, 1e-9);  // 0.05 s past the newest, 10 m/s
  EXPECT_EQ(o.trs_at(kMovingNode, 1.55)->translation.x, 15.0);
  // The oldest kept is the 8th newest (1.2 s): before it, the transforms are forgotten and the animation plays.
  // (A time given as a stamp converts as the frames' times do: 1.2e9 ns * 1e-9 is not the double nearest 1.2.)
  ASSERT_TRUE(o.trs_at(kMovingNode, node_stamp_seconds(1200 * kMs)).has_value());
  EXPECT_EQ(o.trs_at(kMovingNode, node_stamp_seconds(1200 * kMs))->translation.x, 12.0);
  EXPECT_FALSE(o.trs_at(kMovingNode, 1.15).has_value());
  EXPECT_EQ(o.revision(), 20u);
}

TEST(NodeOverrides, LightsAndChildrenFollowAnOverriddenNode) {
  const Scene s = test::animated_scene();
  NodeOverrides o;
  ASSERT_EQ(o.add(s.animation, kMovingNode, 0, at_x(5.0)), NodeTransformVerdict::kAccepted);
  // Light 0 sits 1 m above the node's origin at rest: it moves with the node.
  const SceneLight moved = light_at(s, s.lights[0], 0.3, &o);
  EXPECT_NEAR(moved.position.x, 5.0f, 1e-6f);
  EXPECT_NEAR(moved.position.y, 1.0f, 1e-6f);
  EXPECT_EQ(light_at(s, s.lights[1], 0.3, &o).position, s.lights[1].position);  // the fixed light
  // scene_at moves the node's triangle there; the static one stays.
  const Scene at = scene_at(s, 0.3, &o);
  EXPECT_EQ(at.meshes[1].positions[0], glm::vec3(5.0f, 0.0f, 2.0f));
  EXPECT_EQ(at.meshes[0].positions, s.meshes[0].positions);
  EXPECT_EQ(origin_of(at.meshes[1].T_world_local), glm::dvec3(5.0, 0.0, 2.0));
}

TEST(NodeOverrides, SceneMotionSeesAnAppMoveBetweenTwoTimes) {
  const Scene s = test::animated_scene();
  const SceneMotion motion(s);
  NodeOverrides o;
  ASSERT_EQ(o.add(s.animation, kMovingNode, 1000 * kMs, at_x(-6.0)), NodeTransformVerdict::kAccepted);
  std::vector<WorldBox> boxes;
  // After the stamp, held: nothing moves between two times.
  motion.moved_boxes(1.1, 1.9, boxes, &o);
  EXPECT_TRUE(boxes.empty());
  EXPECT_EQ(motion.moved_lights(1.1, 1.9, &o), 0u);
  // Across the stamp: one box holding the triangle where the animation had it and where the app put it.
  motion.moved_boxes(0.9, 1.1, boxes, &o);
  ASSERT_EQ(boxes.size(), 1u);
  for (const Scene& at : {scene_at(s, 0.9, &o), scene_at(s, 1.1, &o)}) {
    for (const glm::vec3& p : at.meshes[1].positions) EXPECT_TRUE(box_contains(grown(boxes[0], 1e-6), glm::dvec3(p)));
  }
  EXPECT_EQ(motion.moved_lights(0.9, 1.1, &o), 1u);
}

// Determinism: the same transforms give the same bits, whichever object holds them and however often asked.
TEST(NodeOverrides, TheSameTransformsGiveTheSameBits) {
  const Scene s = test::animated_scene();
  NodeOverrides a, b;
  for (NodeOverrides* o : {&a, &b}) {
    ASSERT_EQ(o->add(s.animation, kMovingNode, 300 * kMs, at_x(0.25)), NodeTransformVerdict::kAccepted);
    Trs turned = at_x(0.5);
    turned.rotation = glm::angleAxis(0.3, glm::normalize(glm::dvec3(0.2, 1.0, 0.1)));
    ASSERT_EQ(o->add(s.animation, kMovingNode, 317 * kMs, turned), NodeTransformVerdict::kAccepted);
  }
  const NodeOverrides copy = a;
  for (const double t : {0.1, 0.3, 0.31, 0.317, 0.4, 0.6, 2.5}) {
    EXPECT_EQ(node_world_at(s, kMovingNode, t, &a), node_world_at(s, kMovingNode, t, &b)) << t;
    EXPECT_EQ(node_world_at(s, kMovingNode, t, &a), node_world_at(s, kMovingNode, t, &copy)) << t;
    const Scene x = scene_at(s, t, &a), y = scene_at(s, t, &b);
    EXPECT_EQ(x.meshes[1].positions, y.meshes[1].positions) << t;
    EXPECT_EQ(x.meshes[1].normals, y.meshes[1].normals) << t;
  }
}

// Without overrides (or with an empty set) every function gives exactly what it gave before.
TEST(NodeOverrides, AnEmptySetChangesNothing) {
  const Scene s = test::animated_scene();
  const NodeOverrides none;
  for (const double t : {0.0, 0.4, 1.3}) {
    EXPECT_EQ(node_world_at(s, kMovingNode, t, &none), node_world_at(s, kMovingNode, t));
    EXPECT_EQ(mesh_motion_at(s, s.meshes[1], t, &none), mesh_motion_at(s, s.meshes[1], t));
    EXPECT_EQ(light_at(s, s.lights[0], t, &none).position, light_at(s, s.lights[0], t).position);
  }
}

}  // namespace
}  // namespace dhr
