// PCSS, the client's soft shadow-map lookup for lights with an extent (shaders/client/pcss.h): on the project's
// area-light room the GPU lookup (the compute warp's `local`: every pixel from the shadow maps) equals the CPU
// reference (render/pcss_reference.cpp) on every hard bit and on all but a bounded few soft levels, and the
// forward pass's shadow-map mode (the headset alone) agrees with it; on a synthetic scene (floor, occluder,
// sphere light; the same under a sun, whose fitted orthographic map this also checks) fully lit points see
// level 7, points deep in the occluder's shadow level 0, and the penumbra widens with the light's radius (angle).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "client_test_helpers.hpp"
#include "forward_test_frame.hpp"
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/forward_pass.hpp"
#include "render/light_layout.hpp"
#include "render/pcss_reference.hpp"
#include "render/shadow_maps.hpp"
#include "render/warp_reference.hpp"
#include "scene/scene.hpp"
#include "vk/image.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

namespace fs = std::filesystem;
using ClientPcssTest = vk::test::VulkanTest;
using forward_test::kExtent;
using forward_test::kMargin;
using forward_test::kNear;

Scene area_room() {
  const SceneLoadResult loaded =
      load_scene((fs::path(DHR_SOURCE_DIR) / "assets/scenes/default_room_area.gltf").string());
  if (!loaded) throw std::runtime_error(loaded.error);
  return *loaded.scene;
}

uint32_t level(const VisibilityLayout& layout, uint32_t mask, uint32_t light) {
  return gray_decode(layout.field(mask, light));
}

// The area room, and the same with a sun (directional, 3 degrees wide: a visible penumbra) added.
Scene area_room_with_sun() {
  Scene scene = area_room();
  SceneLight sun;
  sun.type = SceneLight::Type::kDirectional;
  sun.name = "sun";
  sun.direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));
  sun.intensity = 2.0f;
  sun.angle = 0.05f;
  scene.lights.push_back(sun);
  return scene;
}

class ClientPcssRooms : public vk::test::VulkanTest, public testing::WithParamInterface<bool> {};

TEST_P(ClientPcssRooms, GpuLookupEqualsTheCpuReferenceOnTheAreaRoom) {
  const bool with_sun = GetParam();
  const Scene scene = with_sun ? area_room_with_sun() : area_room();
  const VisibilityLayout layout = layout_for_lights(scene.lights);
  ASSERT_TRUE(layout.any_soft());
  const ClientScene gpu_scene(ctx(), scene);
  const ShadowMaps maps(ctx(), gpu_scene);
  const View view = forward_test::traced_view();

  // `local` on the compute warp: G-buffer depth and normals, every pixel from the shadow maps.
  EyePipelineOptions options;
  options.warp.shadow_fill = true;
  EyePipeline eye(ctx(), gpu_scene, kExtent, options);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { eye.record(cmd, 0, view, VisibilityInput{}, {}, &maps); });
  const std::vector<uint32_t> gpu = test::read_pixels<uint32_t>(ctx(), eye.warp().mask);
  const std::vector<float> depth = test::read_pixels<float>(ctx(), eye.gbuffer().depth);
  const std::vector<float> raw_normals = test::read_normals(ctx(), eye.gbuffer().normal);
  std::vector<glm::vec3> normals(raw_normals.size() / 4);
  for (size_t i = 0; i < normals.size(); ++i) {
    normals[i] = glm::vec3(raw_normals[i * 4], raw_normals[i * 4 + 1], raw_normals[i * 4 + 2]);
  }
  std::vector<float> storage;
  const ShadowReference ref = forward_test::shadow_reference(ctx(), maps, storage);
  WarpInput in;
  in.depth = depth;
  in.normals = normals;
  in.display = display_camera(view, kExtent);
  in.near_plane = kNear;
  in.settings.shadow_fill = true;
  in.shadow = &ref;
  in.lights = scene.lights;
  const WarpResult cpu = warp_reference(in);

  size_t surface = 0, hard_compared = 0, hard_differs = 0;
  std::vector<size_t> penumbra(layout.light_count), off_one(layout.light_count), off_more(layout.light_count);
  for (size_t i = 0; i < depth.size(); ++i) {
    if (!(depth[i] > 0.0f)) continue;
    ++surface;
    for (uint32_t l = 0; l < layout.light_count; ++l) {
      if (!layout.is_soft(l)) {
        if (cpu.margin[i] < kMargin) continue;
        ++hard_compared;
        hard_differs += layout.field(gpu[i], l) != layout.field(cpu.masks[i], l) ? 1 : 0;
        continue;
      }
      const uint32_t g = level(layout, gpu[i], l), c = level(layout, cpu.masks[i], l);
      penumbra[l] += c > 0 && c + 1 < kDefaultSoftLevels ? 1 : 0;
      const uint32_t diff = g > c ? g - c : c - g;
      off_one[l] += diff == 1 ? 1 : 0;
      off_more[l] += diff > 1 ? 1 : 0;
    }
  }
  ASSERT_GT(surface, kExtent.width * kExtent.height / 2);
  EXPECT_EQ(hard_differs, 0u) << "of " << hard_compared;
  for (uint32_t l = 0; l < layout.light_count; ++l) {
    if (!layout.is_soft(l)) continue;
    std::printf("pcss light %u (%s): %zu of %zu surface pixels in a penumbra; GPU level differs from the CPU "
                "reference by one on %zu, by more on %zu\n",
                l, scene.lights[l].name.c_str(), penumbra[l], surface, off_one[l], off_more[l]);
    if (scene.lights[l].type != SceneLight::Type::kDirectional) {
      EXPECT_GT(penumbra[l], surface / 200) << "light " << l << ": the view should have soft shadows";
    }
    // A filter tap whose stored depth is within float rounding of its threshold moves the level by one step;
    // a flipped blocker-search tap moves the filter radius and may move it more.
    EXPECT_LE(off_one[l], surface / 100) << "light " << l;
    EXPECT_LE(off_more[l], surface / 1000) << "light " << l;
  }

  // The forward pass's shadow-map mode (the headset alone; interpolated normals instead of the G-buffer's
  // half floats) writes the same levels nearly everywhere.
  ForwardFrame frame;
  frame.display = display_camera(view, kExtent);
  frame.near_plane = kNear;
  frame.lights = scene.lights;
  frame.shadow_maps = &maps;
  const forward_test::ForwardResult fwd = forward_test::run_forward(ctx(), gpu_scene, ForwardMode::kShadowMaps, frame);
  size_t same = 0;
  for (size_t i = 0; i < depth.size(); ++i) same += depth[i] > 0.0f && fwd.mask[i] == gpu[i] ? 1 : 0;
  EXPECT_GE(static_cast<double>(same), 0.98 * static_cast<double>(surface));
}

INSTANTIATE_TEST_SUITE_P(Area, ClientPcssRooms, testing::Values(false, true),
                         [](const testing::TestParamInfo<bool>& p) { return p.param ? "with_sun" : "as_loaded"; });

// A 6 m floor, a 1 m square occluder 0.5 m above it, and `light`.
Scene occluder_scene(const SceneLight& light) {
  Scene scene;
  scene.materials.push_back(test::colour_material({0.8f, 0.8f, 0.8f, 1.0f}));
  scene.meshes.push_back(test::quad_mesh({-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, {-3, 0, -3}, 0));
  scene.meshes.push_back(test::quad_mesh({-0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, {0.5, 0.5, -0.5}, {-0.5, 0.5, -0.5}, 0));
  scene.lights = {light};
  test::finish_scene(scene);
  return scene;
}

// A sphere light 2 m above the floor's centre.
SceneLight sphere_light(float radius) {
  SceneLight light;
  light.type = SceneLight::Type::kPoint;
  light.position = {0.0f, 2.0f, 0.0f};
  light.intensity = 10.0f;
  light.radius = radius;
  return light;
}

// A sun straight down.
SceneLight sun_light(float angle) {
  SceneLight light;
  light.type = SceneLight::Type::kDirectional;
  light.direction = {0.0f, -1.0f, 0.0f};
  light.intensity = 2.0f;
  light.angle = angle;
  return light;
}

// The level PCSS gives floor points (x, 0, z) for x = 0 .. 2.5 m in 5 mm steps.
std::vector<uint32_t> floor_levels(vk::Context& ctx, const SceneLight& light, double z) {
  const Scene scene = occluder_scene(light);
  const VisibilityLayout layout = layout_for_lights(scene.lights);
  EXPECT_TRUE(layout.is_soft(0));
  const ClientScene gpu_scene(ctx, scene);
  const ShadowMaps maps(ctx, gpu_scene);
  std::vector<float> storage;
  const ShadowReference ref = forward_test::shadow_reference(ctx, maps, storage);
  std::vector<uint32_t> levels;
  for (int k = 0; k <= 500; ++k) {
    const glm::dvec3 p(0.005 * k, 0.0, z);
    const ShadowDecision d = shadow_mask_reference(ref, scene.lights, p, glm::dvec3(0, 1, 0), 1e-3);
    levels.push_back(level(layout, d.mask, 0));
  }
  return levels;
}

TEST_F(ClientPcssTest, LitAndShadowedEndsAndAPenumbraThatGrowsWithTheLight) {
  constexpr uint32_t kTop = kDefaultSoftLevels - 1;
  size_t previous_width = 0;
  for (const float radius : {0.03f, 0.1f, 0.25f}) {
    const std::vector<uint32_t> levels = floor_levels(ctx(), sphere_light(radius), 0.1);
    // The occluder's shadow edge is at x = 0.5 * 2 / 1.5 = 0.67 m (from the light's centre).
    EXPECT_EQ(levels.front(), 0u) << "radius " << radius << ": deep in the shadow";
    for (size_t k = 300; k < levels.size(); ++k) ASSERT_EQ(levels[k], kTop) << "radius " << radius << " x " << k * 0.005;
    // Monotonic from shadow to light along the line (the filter may plateau, never turn back).
    for (size_t k = 1; k < levels.size(); ++k) ASSERT_GE(levels[k], levels[k - 1]) << "radius " << radius << " x " << k * 0.005;
    size_t width = 0;
    for (const uint32_t v : levels) width += v > 0 && v < kTop ? 1 : 0;
    std::printf("pcss radius %.2f m: penumbra %zu samples of 5 mm\n", static_cast<double>(radius), width);
    EXPECT_GT(width, previous_width) << "radius " << radius;
    previous_width = width;
  }
}

// The sun's fitted orthographic map (8 mm texels over this 6 m floor): the same checks; the shadow edge is at
// x = 0.5 m, its penumbra 0.5 m x tan(angle / 2) to either side.
TEST_F(ClientPcssTest, SunMapLitAndShadowedEndsAndAPenumbraThatGrowsWithTheAngle) {
  constexpr uint32_t kTop = kDefaultSoftLevels - 1;
  size_t previous_width = 0;
  for (const float angle : {0.05f, 0.15f, 0.3f}) {
    const std::vector<uint32_t> levels = floor_levels(ctx(), sun_light(angle), 0.1);
    EXPECT_EQ(levels.front(), 0u) << "angle " << angle << ": deep in the shadow";
    for (size_t k = 160; k < levels.size(); ++k) ASSERT_EQ(levels[k], kTop) << "angle " << angle << " x " << k * 0.005;
    for (size_t k = 1; k < levels.size(); ++k) ASSERT_GE(levels[k], levels[k - 1]) << "angle " << angle << " x " << k * 0.005;
    size_t width = 0;
    for (const uint32_t v : levels) width += v > 0 && v < kTop ? 1 : 0;
    std::printf("pcss sun angle %.2f rad: penumbra %zu samples of 5 mm\n", static_cast<double>(angle), width);
    EXPECT_GT(width, previous_width) << "angle " << angle;
    previous_width = width;
  }
}

TEST_F(ClientPcssTest, TapCounts) {
  const PcssTaps taps = pcss_taps();
  EXPECT_EQ(taps.search, 16u);
  EXPECT_EQ(taps.filter, 25u);
}

}  // namespace
}  // namespace dhr::render
