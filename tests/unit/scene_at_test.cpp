// scene_at, the exhaustive reference of an animated scene at a scene time: a static scene is copied as it is, a
// moving mesh's vertices land where mesh_motion_at puts them (normals rotated with it), moving lights follow
// light_at, static meshes stay, bounds follow the moved vertices. Scenes are built in code with a hand-made
// animation (one node translated along x and turned about y over a 2 s loop).
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "scene/scene.hpp"
#include "scene/scene_at.hpp"
#include "test_animated_scene.hpp"

namespace dhr {
namespace {

using test::kMovingNode;
using test::kStaticNode;
using test::animated_scene;

void expect_near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

TEST(SceneAt, StaticSceneIsAnIdenticalCopy) {
  Scene s = animated_scene();
  s.animation = SceneAnimation{};
  const Scene at = scene_at(s, 1.25);
  ASSERT_EQ(at.meshes.size(), s.meshes.size());
  for (size_t m = 0; m < s.meshes.size(); ++m) {
    EXPECT_EQ(at.meshes[m].positions, s.meshes[m].positions);
    EXPECT_EQ(at.meshes[m].normals, s.meshes[m].normals);
    EXPECT_EQ(at.meshes[m].T_world_local, s.meshes[m].T_world_local);
  }
  ASSERT_EQ(at.lights.size(), s.lights.size());
  EXPECT_EQ(at.lights[0].position, s.lights[0].position);
  EXPECT_EQ(at.bounds.min, s.bounds.min);
  EXPECT_EQ(at.bounds.max, s.bounds.max);
}

TEST(SceneAt, MovingMeshVerticesLandWhereMeshMotionAtSays) {
  const Scene s = animated_scene();
  for (double t : {0.0, 0.5, 1.0, 1.75, 3.0}) {
    const Scene at = scene_at(s, t);
    const glm::dmat4 motion = mesh_motion_at(s, s.meshes[1], t);
    for (size_t i = 0; i < 3; ++i) {
      const glm::dvec3 expected = glm::dvec3(motion * glm::dvec4(glm::dvec3(s.meshes[1].positions[i]), 1.0));
      expect_near(at.meshes[1].positions[i], glm::vec3(expected));
    }
    EXPECT_EQ(at.meshes[1].T_world_local, node_world_at(s, kMovingNode, t));
    EXPECT_TRUE(at.animation.empty());  // a snapshot
    // The static mesh does not move.
    EXPECT_EQ(at.meshes[0].positions, s.meshes[0].positions);
    EXPECT_EQ(at.meshes[0].normals, s.meshes[0].normals);
  }
  // At t = 1 s: x = 2 m, turned 45 degrees about +y: the rest vertex (1, 0, 2) (1 m along local +x) lands at
  // (2 + cos 45, 0, 2 - sin 45); the +z normal turns to (sin 45, 0, cos 45), still unit length.
  const Scene at = scene_at(s, 1.0);
  const float c = std::sqrt(0.5f);
  expect_near(at.meshes[1].positions[0], glm::vec3(2.0f, 0.0f, 2.0f));
  expect_near(at.meshes[1].positions[1], glm::vec3(2.0f + c, 0.0f, 2.0f - c));
  expect_near(at.meshes[1].normals[0], glm::vec3(c, 0.0f, c));
  EXPECT_NEAR(glm::length(at.meshes[1].normals[2]), 1.0f, 1e-6f);
  // A loop later (2 s) it is where it was at 0.
  const Scene again = scene_at(s, 3.0);
  const Scene first = scene_at(s, 1.0);
  EXPECT_EQ(again.meshes[1].positions, first.meshes[1].positions);
}

TEST(SceneAt, LightsOnMovingNodesMove) {
  const Scene s = animated_scene();
  const Scene at = scene_at(s, 1.0);
  const SceneLight expected = light_at(s, s.lights[0], 1.0);
  EXPECT_EQ(at.lights[0].position, expected.position);
  EXPECT_EQ(at.lights[0].direction, expected.direction);
  // The light sits 1 m above the node's origin: it moves with it to (2, 1, 2).
  expect_near(at.lights[0].position, glm::vec3(2.0f, 1.0f, 2.0f));
  // A light without a node stays.
  EXPECT_EQ(at.lights[1].position, s.lights[1].position);
}

TEST(SceneAt, BoundsFollowTheMovedVertices) {
  const Scene s = animated_scene();
  EXPECT_NEAR(s.bounds.max.x, 1.0f, 0.0f);
  const Scene at = scene_at(s, 1.0);
  SceneBounds expected;
  for (const SceneMesh& m : at.meshes) {
    for (const glm::vec3& p : m.positions) expected.extend(p);
  }
  EXPECT_EQ(at.bounds.min, expected.min);
  EXPECT_EQ(at.bounds.max, expected.max);
  EXPECT_NEAR(at.bounds.max.x, 2.0f + std::sqrt(0.5f), 1e-5f);
}

}  // namespace
}  // namespace dhr
