// SceneMotion: what moved between two scene times (the boxes of moved meshes at both times, the lights that moved),
// checked against scene_at (every moved vertex lies in the box of its time) and the segment/box tests the warp uses.
#include <gtest/gtest.h>

#include <vector>

#include "scene/scene_at.hpp"
#include "scene/scene_motion.hpp"
#include "test_animated_scene.hpp"

namespace dhr {
namespace {

TEST(SceneMotion, AStaticSceneNeverMoves) {
  Scene s = test::animated_scene();
  s.animation = SceneAnimation{};
  const SceneMotion motion(s);
  EXPECT_FALSE(motion.moves());
  std::vector<WorldBox> boxes(3);
  motion.moved_boxes(0.0, 1.0, boxes);
  EXPECT_TRUE(boxes.empty());
  EXPECT_EQ(motion.moved_lights(0.0, 1.0), 0u);
}

TEST(SceneMotion, TheMovedNodeGivesOneBoxHoldingItsMeshesAtBothTimes) {
  const Scene s = test::animated_scene();
  const SceneMotion motion(s);
  EXPECT_TRUE(motion.moves());
  EXPECT_EQ(motion.moving_meshes(), 1u);
  EXPECT_EQ(motion.moving_lights(), 1u);  // light 0 rides the moving node, light 1 is fixed
  std::vector<WorldBox> boxes;
  const double t0 = 0.25, t1 = 0.7;
  motion.moved_boxes(t0, t1, boxes);
  ASSERT_EQ(boxes.size(), 1u);
  for (const double t : {t0, t1}) {
    const Scene at = scene_at(s, t);
    for (const glm::vec3& p : at.meshes[1].positions) {
      EXPECT_TRUE(box_contains(grown(boxes[0], 1e-6), glm::dvec3(p))) << "time " << t;
    }
  }
  // The static triangle is in neither box (it is 2 m away along z).
  EXPECT_FALSE(box_contains(boxes[0], glm::dvec3(0.2, 0.2, 0.0)));
  EXPECT_EQ(motion.moved_lights(t0, t1), 1u);
}

TEST(SceneMotion, MeshesOfOneNodeShareItsBox) {
  Scene s = test::animated_scene();
  SceneMesh second = s.meshes[1];
  for (glm::vec3& p : second.positions) p += glm::vec3(0.0f, 3.0f, 0.0f);  // 3 m above, on the same node
  s.meshes.push_back(second);
  const SceneMotion motion(s);
  EXPECT_EQ(motion.moving_meshes(), 2u);
  std::vector<WorldBox> boxes;
  motion.moved_boxes(0.1, 0.2, boxes);
  ASSERT_EQ(boxes.size(), 1u);
  for (const std::size_t m : {std::size_t{1}, std::size_t{2}}) {
    for (const double t : {0.1, 0.2}) {
      const Scene at = scene_at(s, t);
      for (const glm::vec3& p : at.meshes[m].positions) {
        EXPECT_TRUE(box_contains(grown(boxes[0], 1e-6), glm::dvec3(p))) << "mesh " << m << " time " << t;
      }
    }
  }
}

TEST(SceneMotion, OverlappingBoxesOfTwoNodesAreMerged) {
  Scene s = test::animated_scene();
  // A second moving node (2) with a triangle 0.5 m beside the first one's: their boxes overlap; a third (3) far away.
  for (const std::uint32_t node : {2u, 3u}) {
    SceneMesh m = s.meshes[1];
    m.node = node;
    const glm::vec3 offset = node == 2 ? glm::vec3(0.5f, 0.0f, 0.0f) : glm::vec3(0.0f, 50.0f, 0.0f);
    for (glm::vec3& p : m.positions) p += offset;
    m.T_world_local = glm::translate(m.T_world_local, glm::dvec3(offset));
    s.meshes.push_back(m);
    AnimatedNode n = s.animation.nodes[0];
    n.node = node;
    n.translation += glm::dvec3(offset);
    n.rest_local = glm::translate(glm::dmat4(1.0), n.translation);
    n.rest_world = n.rest_local;
    n.first_track = static_cast<std::uint32_t>(s.animation.tracks.size());
    for (std::uint32_t k = 0; k < 2; ++k) {
      AnimationTrack t = s.animation.tracks[k];
      t.node = node;
      if (t.path == AnimationPath::kTranslation) {
        for (std::size_t v = 0; v < t.values.size(); v += 3) {
          t.values[v] += offset.x;
          t.values[v + 1] += offset.y;
        }
      }
      s.animation.tracks.push_back(t);
    }
    s.animation.nodes.push_back(n);
    s.animation.moving_nodes.push_back(node);
  }
  const SceneMotion motion(s);
  std::vector<WorldBox> boxes;
  motion.moved_boxes(0.1, 0.2, boxes);
  ASSERT_EQ(boxes.size(), 2u);  // nodes 1 and 2 merged, node 3 alone
  for (const double t : {0.1, 0.2}) {
    const Scene at = scene_at(s, t);
    for (std::size_t m = 1; m < at.meshes.size(); ++m) {
      for (const glm::vec3& p : at.meshes[m].positions) {
        EXPECT_TRUE(box_contains(grown(boxes[0], 1e-6), glm::dvec3(p)) || box_contains(grown(boxes[1], 1e-6), glm::dvec3(p)))
            << "mesh " << m << " time " << t;
      }
    }
  }
  EXPECT_TRUE(boxes_overlap(WorldBox{glm::dvec3(0.0), glm::dvec3(1.0)}, WorldBox{glm::dvec3(1.0), glm::dvec3(2.0)}));
  EXPECT_FALSE(boxes_overlap(WorldBox{glm::dvec3(0.0), glm::dvec3(1.0)}, WorldBox{glm::dvec3(1.1), glm::dvec3(2.0)}));
}

TEST(SceneMotion, NothingMovedAtTheSameTimeOrAFullLoopLater) {
  const Scene s = test::animated_scene();
  const SceneMotion motion(s);
  std::vector<WorldBox> boxes;
  motion.moved_boxes(0.5, 0.5, boxes);
  EXPECT_TRUE(boxes.empty());
  EXPECT_EQ(motion.moved_lights(0.5, 0.5), 0u);
  motion.moved_boxes(0.5, 2.5, boxes);  // the animation loops every 2 s
  EXPECT_TRUE(boxes.empty());
  EXPECT_EQ(motion.moved_lights(0.5, 2.5), 0u);
}

TEST(SceneMotion, SegmentAndBoxTests) {
  const WorldBox box{glm::dvec3(0.0), glm::dvec3(1.0)};
  EXPECT_TRUE(segment_hits_box({-1, 0.5, 0.5}, {2, 0.5, 0.5}, box));    // through
  EXPECT_TRUE(segment_hits_box({0.5, 0.5, 0.5}, {0.6, 0.6, 0.6}, box));  // inside
  EXPECT_TRUE(segment_hits_box({0.5, 0.5, -1}, {0.5, 0.5, 0.0}, box));   // ends on a face
  EXPECT_FALSE(segment_hits_box({-1, 0.5, 0.5}, {-0.1, 0.5, 0.5}, box));  // stops short
  EXPECT_FALSE(segment_hits_box({-1, 2, 0.5}, {2, 2, 0.5}, box));         // passes above
  EXPECT_FALSE(segment_hits_box({-1, 1.5, 0.5}, {1.5, 3, 0.5}, box));     // diagonal miss
  EXPECT_TRUE(segment_hits_box({0.5, 2, 0.5}, {0.5, 2, 0.5}, grown(box, 1.0)));  // a point in the grown box
  EXPECT_TRUE(box_contains(box, {1, 1, 1}));
  EXPECT_FALSE(box_contains(box, {1, 1, 1.001}));
}

}  // namespace
}  // namespace dhr
