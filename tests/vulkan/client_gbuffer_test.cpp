// G-buffer pass: depth, normal and albedo of hand-made quads at pixel centres; world positions from depth;
// back-face culling; textures; camera-relative precision far from the origin.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "client_test_helpers.hpp"
#include "render/client_scene.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/render_camera.hpp"
#include "gbuffer_readback.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using ClientGBufferTest = vk::test::VulkanTest;

constexpr Extent kExtent{96, 72};
constexpr double kNear = kDefaultNearPlane;

using test::GBufferReadback;

// Renders `scene` from `view` and reads the three images back.
GBufferReadback render(vk::Context& ctx, const Scene& scene, const View& view) {
  const ClientScene gpu_scene(ctx, scene);
  return test::render_gbuffer(ctx, gpu_scene, display_camera(view, kExtent), kNear);
}

// A camera at `offset` looking down -Z (tangents 0.5 x 0.375) and a quad 2 m ahead, x in [-0.5, 0.5],
// y in [-0.25, 0.25] (dyadic, so it stays exact in float when offset by 1e4 m).
Scene front_quad_scene(const glm::dvec3& offset, const glm::vec4& colour, bool double_sided, bool facing_camera) {
  Scene scene;
  scene.materials.push_back(test::colour_material(colour, double_sided));
  const glm::dvec3 a = offset + glm::dvec3(-0.5, -0.25, -2.0), b = offset + glm::dvec3(0.5, -0.25, -2.0);
  const glm::dvec3 c = offset + glm::dvec3(0.5, 0.25, -2.0), d = offset + glm::dvec3(-0.5, 0.25, -2.0);
  scene.meshes.push_back(facing_camera ? test::quad_mesh(a, b, c, d, 0) : test::quad_mesh(a, d, c, b, 0));
  test::finish_scene(scene);
  return scene;
}

View front_view(const glm::dvec3& offset) {
  View view;
  view.pose.position = offset;
  view.fov = test::fov_from_tangents(0.5, 0.375);
  return view;
}

// Pixels whose centre is inside the quad of front_quad_scene: tx = -0.5 + (i + 0.5) / 96 in
// [-0.25, 0.25] and ty = 0.375 - (j + 0.5) * 0.75 / 72 in [-0.125, 0.125].
bool inside_front_quad(uint32_t i, uint32_t j) {
  const double tx = -0.5 + (i + 0.5) / 96.0, ty = 0.375 - (j + 0.5) * 0.75 / 72.0;
  return std::abs(tx) < 0.25 && std::abs(ty) < 0.125;
}

TEST_F(ClientGBufferTest, FrontQuadDepthNormalAlbedoAtPixelCentres) {
  const glm::vec4 colour(0.2f, 0.4f, 0.6f, 1.0f);
  const GBufferReadback g = render(ctx(), front_quad_scene(glm::dvec3(0.0), colour, false, true),
                                   front_view(glm::dvec3(0.0)));
  const float expected_depth = static_cast<float>(kNear / 2.0);
  size_t covered = 0;
  for (uint32_t j = 0; j < kExtent.height; ++j) {
    for (uint32_t i = 0; i < kExtent.width; ++i) {
      const size_t p = size_t{j} * kExtent.width + i;
      if (inside_front_quad(i, j)) {
        ++covered;
        ASSERT_NEAR(g.depth[p], expected_depth, 1e-9f) << i << "," << j;
        ASSERT_EQ(g.normal[p * 4 + 0], 0.0f);
        ASSERT_EQ(g.normal[p * 4 + 1], 0.0f);
        ASSERT_EQ(g.normal[p * 4 + 2], 1.0f);
        ASSERT_EQ(g.normal[p * 4 + 3], 1.0f);
        ASSERT_EQ(g.albedo[p * 4 + 0], 51);  // 0.2 * 255
        ASSERT_EQ(g.albedo[p * 4 + 1], 102);
        ASSERT_EQ(g.albedo[p * 4 + 2], 153);
        ASSERT_EQ(g.albedo[p * 4 + 3], 255);
      } else {
        ASSERT_EQ(g.depth[p], 0.0f) << "background at " << i << "," << j;
        ASSERT_EQ(g.albedo[p * 4 + 3], 0);
        ASSERT_EQ(g.normal[p * 4 + 3], 0.0f);
      }
    }
  }
  EXPECT_EQ(covered, 48u * 24u);
}

TEST_F(ClientGBufferTest, BackFacesCulledUnlessDoubleSided) {
  const glm::vec4 colour(1.0f);
  // Single-sided, seen from behind: nothing drawn.
  const GBufferReadback culled = render(ctx(), front_quad_scene(glm::dvec3(0.0), colour, false, false),
                                        front_view(glm::dvec3(0.0)));
  for (float d : culled.depth) ASSERT_EQ(d, 0.0f);
  // Double-sided, seen from behind: drawn, normal flipped toward the viewer (+Z).
  const GBufferReadback both = render(ctx(), front_quad_scene(glm::dvec3(0.0), colour, true, false),
                                      front_view(glm::dvec3(0.0)));
  const size_t p = size_t{36} * kExtent.width + 48;
  ASSERT_TRUE(inside_front_quad(48, 36));
  EXPECT_GT(both.depth[p], 0.0f);
  EXPECT_EQ(both.normal[p * 4 + 2], 1.0f);
}

TEST_F(ClientGBufferTest, WorldPositionsFromDepthMatchTheAnalyticFloor) {
  // A floor (y = -1) from 1 m to 20 m ahead, seen from a camera pitched down by 20 degrees.
  Scene scene;
  scene.materials.push_back(test::colour_material(glm::vec4(0.5f)));
  scene.meshes.push_back(test::quad_mesh({-8.0, -1.0, -1.0}, {8.0, -1.0, -1.0}, {8.0, -1.0, -20.0},
                                         {-8.0, -1.0, -20.0}, 0));
  test::finish_scene(scene);
  View view;
  view.pose = test::rotated(Pose{}, 0.0, -20.0);
  view.fov = test::fov_from_tangents(0.6, 0.45);
  const GBufferReadback g = render(ctx(), scene, view);
  const Camera camera = display_camera(view, kExtent);
  // A rasterizer snaps vertices to its sub-pixel grid (subPixelPrecisionBits; 8 on lavapipe and NVIDIA), so
  // the depth at a pixel centre is the floor's at a point up to that far away: the bound is the floor's
  // movement over twice that step in x and in y (3 mm far away on an NVIDIA H100), plus 0.1 mm.
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(ctx().physical_device(), &properties);
  const double snap = 2.0 / static_cast<double>(1u << properties.limits.subPixelPrecisionBits);
  const auto floor_at = [&](double x, double y) {
    const glm::dvec3 ray = camera.world_ray(x, y);
    return ray.y < 0.0 ? glm::dvec3(-1.0 / ray.y * ray) : glm::dvec3(std::nan(""));  // hit of y = -1
  };
  size_t checked = 0;
  double worst = 0.0, worst_over_bound = 0.0;
  for (uint32_t j = 0; j < kExtent.height; ++j) {
    for (uint32_t i = 0; i < kExtent.width; ++i) {
      const float d = g.depth[size_t{j} * kExtent.width + i];
      const glm::dvec3 ray = camera.world_ray(i + 0.5, j + 0.5);
      const double t = ray.y < 0.0 ? -1.0 / ray.y : -1.0;  // hit of y = -1 from the origin
      const glm::dvec3 hit = t * ray;
      const bool on_floor = t > 0.0 && hit.z < -1.0 && hit.z > -20.0 && std::abs(hit.x) < 8.0;
      const bool near_edge = t > 0.0 && (std::abs(hit.z + 1.0) < 0.05 || std::abs(hit.z + 20.0) < 0.3);
      if (near_edge) continue;
      ASSERT_EQ(d > 0.0f, on_floor) << i << "," << j;
      if (!on_floor) continue;
      const glm::dvec3 p = world_point_from_depth(camera, kNear, i + 0.5, j + 0.5, d);
      const double bound = 1e-4 + glm::length(floor_at(i + 0.5 + snap, j + 0.5) - hit) +
                           glm::length(floor_at(i + 0.5, j + 0.5 + snap) - hit);
      worst = std::max(worst, glm::length(p - hit));
      worst_over_bound = std::max(worst_over_bound, glm::length(p - hit) / bound);
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000u);
  EXPECT_LT(worst_over_bound, 1.0) << "worst reconstruction error " << worst << " m";
}

TEST_F(ClientGBufferTest, TextureTimesFactorIsLinearAlbedo) {
  Scene scene;
  SceneImage image;
  image.name = "flat";
  image.width = 4;
  image.height = 4;
  image.rgba8.assign(4 * 4 * 4, 200);  // sRGB 200 everywhere: filtering cannot change it
  scene.images.push_back(image);
  SceneMaterial m = test::colour_material(glm::vec4(0.5f, 1.0f, 0.25f, 1.0f));
  m.base_color_image = 0;
  scene.materials.push_back(m);
  scene.meshes.push_back(test::quad_mesh({-0.5, -0.25, -2.0}, {0.5, -0.25, -2.0}, {0.5, 0.25, -2.0},
                                         {-0.5, 0.25, -2.0}, 0));
  test::finish_scene(scene);
  const GBufferReadback g = render(ctx(), scene, front_view(glm::dvec3(0.0)));
  const double linear = std::pow((200.0 / 255.0 + 0.055) / 1.055, 2.4);
  const size_t p = size_t{36} * kExtent.width + 48;
  EXPECT_NEAR(g.albedo[p * 4 + 0], std::round(linear * 0.5 * 255.0), 1.0);
  EXPECT_NEAR(g.albedo[p * 4 + 1], std::round(linear * 255.0), 1.0);
  EXPECT_NEAR(g.albedo[p * 4 + 2], std::round(linear * 0.25 * 255.0), 1.0);
}

TEST_F(ClientGBufferTest, SameSceneFarFromTheOriginGivesTheSameGBuffer) {
  const glm::vec4 colour(0.2f, 0.4f, 0.6f, 1.0f);
  const glm::dvec3 far(1.0e4, 2.0e4, -1.0e4);
  const GBufferReadback near_origin = render(ctx(), front_quad_scene(glm::dvec3(0.0), colour, false, true),
                                             front_view(glm::dvec3(0.0)));
  const GBufferReadback offset = render(ctx(), front_quad_scene(far, colour, false, true), front_view(far));
  EXPECT_EQ(offset.normal, near_origin.normal);
  EXPECT_EQ(offset.albedo, near_origin.albedo);
  ASSERT_EQ(offset.depth.size(), near_origin.depth.size());
  for (size_t i = 0; i < offset.depth.size(); ++i) {
    ASSERT_NEAR(offset.depth[i], near_origin.depth[i], 1e-7f) << i;
  }
}

TEST_F(ClientGBufferTest, CameraExtentMustMatchTheTargets) {
  const Scene scene = front_quad_scene(glm::dvec3(0.0), glm::vec4(1.0f), false, true);
  const ClientScene gpu_scene(ctx(), scene);
  const GBufferPass pass(ctx(), gpu_scene);
  GBuffer targets = GBuffer::create(ctx(), kExtent);
  const Camera wrong = display_camera(front_view(glm::dvec3(0.0)), Extent{64, 64});
  EXPECT_THROW(ctx().submit_and_wait([&](VkCommandBuffer cmd) { pass.record(cmd, targets, wrong, kNear); }),
               std::invalid_argument);
}

TEST_F(ClientGBufferTest, InconsistentScenesAreRejected) {
  Scene scene = front_quad_scene(glm::dvec3(0.0), glm::vec4(1.0f), false, true);
  scene.meshes[0].normals.pop_back();
  EXPECT_THROW(ClientScene(ctx(), scene), std::invalid_argument);
  scene = front_quad_scene(glm::dvec3(0.0), glm::vec4(1.0f), false, true);
  scene.meshes[0].indices.push_back(7);
  EXPECT_THROW(ClientScene(ctx(), scene), std::invalid_argument);
  scene = front_quad_scene(glm::dvec3(0.0), glm::vec4(1.0f), false, true);
  scene.meshes[0].material = 3;
  EXPECT_THROW(ClientScene(ctx(), scene), std::invalid_argument);
}

}  // namespace
}  // namespace dhr::render
