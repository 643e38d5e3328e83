// The bound between the backends for soft levels (docs/server.md, "Soft levels in a session"): the Vulkan tracer
// does not sample yet, so its trace_layout writes each soft light's centre ray as level 0 or 7. On
// default_room_area.gltf (a rect, a punctual and a sphere light): its hard fields are its own trace_lights bits
// (which agree with Embree's by the usual criterion), its soft fields its centre bits widened; against Embree's
// sampled fields, the soft pairs whose sampled fraction is exactly 0 or 1 get the same level except within a
// pixel of a silhouette or a shadow boundary (measured share printed, bounded).
#include "vulkan_tracer_agreement.hpp"

#include "trace/soft/soft_image.hpp"

#include <cstdio>

namespace dhr::server::tracer_test {
namespace {

constexpr const char* kAreaScene = "assets/scenes/default_room_area.gltf";

TEST_F(VulkanTracerTest, SoftLayoutIsTheCentreRayWidenedAndMatchesEmbreeWhereSamplingIsUniform) {
  const std::string path = test::source_path(kAreaScene);
  const Scene scene = load_scene_or_fail(path);
  const auto cameras = bookmark_cameras(path, {96, 72});
  ASSERT_FALSE(cameras.empty());
  EmbreeTracer embree(scene, embree_options());
  VulkanTracer vulkan(scene, vk_options());
  ASSERT_EQ(vulkan.light_extents(), embree.light_extents());
  const uint32_t n = vulkan.light_count();
  const VisibilityLayout layout = layout_for_lights(vulkan.light_extents(), n);
  ASSERT_TRUE(layout.any_soft());
  uint64_t uniform = 0, disagree = 0;
  for (const Camera& camera : cameras) {
    VisibilityBuffer vk_fields, vk_bits, em_fields;
    TraceStats st;
    vulkan.trace_layout(camera, layout, vk_fields, st);
    vulkan.trace_lights(camera, n, vk_bits, st);
    embree.trace_layout(camera, layout, em_fields, st);
    SoftImage soft;
    SoftImageOptions so;
    so.threads = 2;
    trace_soft_image(embree.embree_scene(), scene.lights, camera, so, soft);
    VisibilityBuffer widened;
    widen_to_layout(vk_bits, layout, widened);
    ASSERT_TRUE(vk_fields == widened);  // hard fields: its bits; soft fields: its centre bits as level 0 or 7
    for (uint32_t y = 0; y < camera.extent.height; ++y) {
      for (uint32_t x = 0; x < camera.extent.width; ++x) {
        for (uint32_t l = 0; l < n; ++l) {
          if (!layout.is_soft(l)) continue;
          const size_t i = soft.index(x, y, l);
          if (soft.rays[i] == 0 || (soft.fraction[i] != 0.0f && soft.fraction[i] != 1.0f)) continue;
          ++uniform;
          if (layout.field(vk_fields.get(x, y), l) != layout.field(em_fields.get(x, y), l)) ++disagree;
        }
      }
    }
  }
  ASSERT_GT(uniform, 0u);
  const double share = static_cast<double>(disagree) / static_cast<double>(uniform);
  std::printf("[ soft bound ] vulkan vs embree: %llu of %llu soft pairs with sampled fraction 0 or 1 differ (%.4f %%)\n",
              static_cast<unsigned long long>(disagree), static_cast<unsigned long long>(uniform), 100.0 * share);
  EXPECT_LT(share, 0.005);
}

}  // namespace
}  // namespace dhr::server::tracer_test
