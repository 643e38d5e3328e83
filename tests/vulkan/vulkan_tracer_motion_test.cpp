// The Vulkan tracer on moving scenes (issue 27): moving meshes by their instance transforms with a TLAS update, their
// shading vertices and the moved lights re-uploaded, against the Embree backend at the same scene times.
#include "vulkan_tracer_agreement.hpp"

#include <string>
#include <vector>

#include "moving_scene.hpp"
#include "scene/node_overrides.hpp"
#include "test_scenes.hpp"

namespace dhr::server::tracer_test {
namespace {

Camera occluder_camera() { return test::look_camera({0.8, 2.2, 1.6}, {1.0, 0.9, 0.0}, 160, 120, 70.0); }

// The client tests' moving scene as it is: its quads all leave SceneMesh::geometry 0, and the plan shares a BLAS only
// between meshes whose local vertices agree.
Scene moving_scene() { return render::moving_scene(); }

TEST_F(VulkanTracerTest, MovingSceneAgreesWithEmbreeAtEveryTime) {
  const Scene scene = moving_scene();
  const std::vector<double> times{0.0, 0.5, 1.0, 1.7, 2.5};
  expect_agreement(scene, {occluder_camera()}, vk_options(), embree_options(), {}, times);
  VulkanTracerConfig world_blas;  // moving meshes in scene-relative BLASes, moved by the instance transform alone
  world_blas.instanced = false;
  expect_agreement(scene, {occluder_camera()}, vk_options(), embree_options(), world_blas, times);
}

TEST_F(VulkanTracerTest, TheOccludersShadowMovesWithTheSceneTime) {
  const Scene scene = moving_scene();
  VulkanTracer vulkan(scene, vk_options());
  EXPECT_TRUE(vulkan.moves());
  const Camera camera = occluder_camera();
  VisibilityBuffer at_rest, later, back;
  TraceStats stats;
  vulkan.trace(camera, at_rest, stats);
  vulkan.set_scene_time(1.0);
  EXPECT_GT(vulkan.last_motion_update_ms(), 0.0);
  vulkan.trace(camera, later, stats);
  size_t changed = 0;
  for (uint32_t y = 0; y < camera.extent.height; ++y)
    for (uint32_t x = 0; x < camera.extent.width; ++x)
      if ((at_rest.get(x, y) & 1u) != (later.get(x, y) & 1u)) ++changed;  // light A, above the occluder
  EXPECT_GT(changed, 100u) << "the occluder moved 1 m: its shadow under light A must move";
  // Back to the rest pose: the same bits as before (the update is exact, not drifting).
  vulkan.set_scene_time(0.0);
  vulkan.trace(camera, back, stats);
  EXPECT_EQ(back.data, at_rest.data);
  EXPECT_EQ(vulkan.validation_error_count(), 0u);
}

TEST_F(VulkanTracerTest, AStaticSceneDoesNotMove) {
  const Scene scene = load_scene_or_fail(test::source_path(kDefaultScenePath));
  VulkanTracer vulkan(scene, vk_options());
  EXPECT_FALSE(vulkan.moves());
  vulkan.set_scene_time(3.0);  // nothing to move
  EXPECT_EQ(vulkan.last_motion_update_ms(), 0.0);
}

// An app-moved node (docs/motion.md): the animated occluder overridden by an app's transform; both backends trace
// it where the transform puts it, not where its animation has it.
TEST_F(VulkanTracerTest, AnAppMovedNodeAgreesWithEmbree) {
  const Scene scene = moving_scene();
  EmbreeTracer embree(scene, embree_options());
  VulkanTracer vulkan(scene, vk_options());
  ASSERT_NE(vulkan.scene_animation(), nullptr);
  const Camera camera = occluder_camera();
  const double t = 0.5;
  VisibilityBuffer animated, ref, got;
  TraceStats stats;
  vulkan.set_scene_time(t);
  vulkan.trace(camera, animated, stats);
  NodeOverrides overrides;
  const Trs app{glm::dvec3(-0.6, 1.0, 0.2), glm::angleAxis(0.4, glm::dvec3(1.0, 0.0, 0.0)), glm::dvec3(1.5)};
  ASSERT_EQ(overrides.add(*vulkan.scene_animation(), render::kOccluderNode, 250'000'000, app),
            NodeTransformVerdict::kAccepted);
  embree.set_scene_time(t, &overrides);
  vulkan.set_scene_time(t, &overrides);
  embree.trace(camera, ref, stats);
  vulkan.trace(camera, got, stats);
  size_t differing = 0, moved = 0;
  for (uint32_t y = 0; y < camera.extent.height; ++y)
    for (uint32_t x = 0; x < camera.extent.width; ++x) {
      differing += ref.get(x, y) != got.get(x, y);
      moved += animated.get(x, y) != got.get(x, y);
    }
  EXPECT_EQ(differing, 0u) << "Vulkan and Embree disagree with the app's transform";
  EXPECT_GT(moved, 50u) << "the app put the occluder elsewhere than its animation: its shadow must differ";
  EXPECT_EQ(vulkan.validation_error_count(), 0u);
}

TEST_F(VulkanTracerTest, LivingRoomMovingAgreesWithEmbreeWhileTheCarDrives) {
  const std::string path = test::shared_data_path("scenes/living_room_moving.glb");
  if (path.empty()) GTEST_SKIP() << "../shared/data not present: living_room_moving.glb comparison skipped";
  const Scene scene = load_scene_or_fail(path);
  const auto cameras = bookmark_cameras(path, {96, 72});
  ASSERT_FALSE(cameras.empty());
  expect_agreement(scene, cameras, vk_options(), embree_options(), {}, {0.0, 1.3, 2.9, 4.6});
}

}  // namespace
}  // namespace dhr::server::tracer_test
