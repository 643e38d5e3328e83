// The Vulkan tracer with more than 32 lights (light slots, scene/light_slots.hpp): the same slots as the Embree
// backend, and its bits agree with Embree's by the usual criterion (vulkan_tracer_agreement.hpp) on the test floor
// with 64 point lights (10 to 20 slots), with the skips on and off; a soft light in a slot takes the same levels.
#include "test_animated_scene.hpp"
#include "vulkan_tracer_agreement.hpp"

namespace dhr::server::tracer_test {
namespace {

TEST_F(VulkanTracerTest, LightSlotsAgreeWithEmbree) {
  const Scene scene = test::many_lights_floor(8, 1.0f);  // 64 lights
  VulkanTracer vulkan(scene, vk_options());
  EmbreeTracer embree(scene, embree_options());
  ASSERT_NE(vulkan.light_slots(), nullptr);
  ASSERT_NE(embree.light_slots(), nullptr);
  EXPECT_EQ(*vulkan.light_slots(), *embree.light_slots());
  EXPECT_EQ(vulkan.light_count(), embree.light_count());
  const std::vector<Camera> cameras = {test::many_lights_camera(160, 120),
                                       test::look_camera(glm::dvec3(1.0, 1.6, -0.5), glm::dvec3(4.0, 0.0, 4.0), 96, 72)};
  expect_agreement(scene, cameras, vk_options(), embree_options());
  TracerOptions embree_all = embree_options();
  embree_all.skip = SkipOptions::none();
  expect_agreement(scene, cameras, vk_options(SkipOptions::none()), embree_all);
}

TEST_F(VulkanTracerTest, LightSlotsWithASoftLightAgreeWithEmbree) {
  const Scene scene = test::many_lights_floor(7, 1.0f, /*soft_first=*/true);  // 49 lights, light 0 a sphere
  VulkanTracer vulkan(scene, vk_options());
  EmbreeTracer embree(scene, embree_options());
  const VisibilityLayout layout = layout_for_lights(embree.light_extents(), embree.light_count());
  ASSERT_TRUE(layout.any_soft());
  const Camera camera = test::many_lights_camera(96, 72);
  VisibilityBuffer got, ref;
  TraceStats got_stats, ref_stats;
  vulkan.trace_layout(camera, layout, got, got_stats);
  embree.trace_layout(camera, layout, ref, ref_stats);
  ASSERT_EQ(got.light_count, ref.light_count);
  uint64_t differing = 0;
  for (size_t p = 0; p < ref.pixel_count(); ++p) differing += got.mask_at(p) != ref.mask_at(p);
  // Measured on lavapipe: identical. A GPU's float may move a sample grazing an edge (the soft layout test's bound).
  EXPECT_LE(differing, ref.pixel_count() / 200) << differing << " pixels differ";
  EXPECT_EQ(got_stats.soft_pairs, ref_stats.soft_pairs);
  EXPECT_GT(got_stats.soft_pairs, 0u);
}

TEST_F(VulkanTracerTest, LightSlotsRefuseAMovingScene) {
  Scene scene = test::many_lights_floor(6, 0.9f);  // 36 lights
  test::animate_translation(scene, 0, glm::vec3(0.0f), glm::vec3(1, 0, 0), 2.0);
  EXPECT_THROW(VulkanTracer(scene, vk_options()), std::runtime_error);
}

}  // namespace
}  // namespace dhr::server::tracer_test
