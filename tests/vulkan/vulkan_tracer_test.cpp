// The Vulkan visibility tracer against the Embree reference (lavapipe, validation layer on, zero errors;
// real scenes: vulkan_tracer_real_scene_test.cpp): build variants, hand-made scenes for culling /
// double-sided / mirrored instances, area lights, skipping that changes no bit, statistics, mask widths, far-from-origin precision, bad input.
#include "test_scenes.hpp"
#include "vulkan_tracer_agreement.hpp"
#include "trace/vulkan/vulkan_tracer_internal.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

namespace dhr::server {
namespace {

using test::add_grid;
using test::finalize;

using namespace tracer_test;

TEST_F(VulkanTracerTest, FlattenedUnsortedBuildAgreesToo) {
  const std::string path = test::source_path(kDefaultScenePath);
  const Scene scene = load_scene_or_fail(path);
  const auto cameras = bookmark_cameras(path, {96, 72});
  VulkanTracerConfig config;
  config.instanced = false;
  config.morton_sort = false;
  config.compact = false;
  expect_agreement(scene, cameras, vk_options(), embree_options(), config);
}

// Rect and sphere lights (the default room's sibling): light_eval.h's one-sided test and the shadow ray to the
// centre agree between the ray-tracing shader and Embree.
TEST_F(VulkanTracerTest, AreaAndSphereLightsAgreeWithEmbree) {
  const std::string path = test::source_path("assets/scenes/default_room_area.gltf");
  const Scene scene = load_scene_or_fail(path);
  ASSERT_EQ(scene.lights[0].type, SceneLight::Type::kRect);
  expect_agreement(scene, bookmark_cameras(path, {96, 72}), vk_options(), embree_options());
}

TEST_F(VulkanTracerTest, SkippingChangesNoBit) {
  const std::string path = test::source_path(kDefaultScenePath);
  const Scene scene = load_scene_or_fail(path);
  VulkanTracer skipping(scene, vk_options());
  VulkanTracer exhaustive(scene, vk_options(SkipOptions::none()));
  for (const Camera& camera : bookmark_cameras(path, {128, 96})) {
    VisibilityBuffer a, b;
    TraceStats sa, sb;
    skipping.trace(camera, a, sa);
    exhaustive.trace(camera, b, sb);
    EXPECT_TRUE(a == b);
    const uint64_t hit = sa.pixels - sa.background_pixels;
    EXPECT_EQ(sb.background_pixels, sa.background_pixels);
    EXPECT_EQ(sb.shadow_rays, hit * scene.lights.size());
    EXPECT_EQ(sb.skipped_backfacing + sb.skipped_out_of_range + sb.skipped_culled_light, 0u);
    EXPECT_LE(sa.shadow_rays, sb.shadow_rays);
    EXPECT_GT(sa.skipped_backfacing, 0u);
  }
}

// A client asking for the first N lights: the same bits as the full trace for those lights, and the shader
// never tests or traces the others (exhaustive: exactly hit pixels x N shadow rays).
TEST_F(VulkanTracerTest, LightSubsetHasTheFullTracesBitsAndNoRaysForTheOthers) {
  const std::string path = test::source_path(kDefaultScenePath);
  const Scene scene = load_scene_or_fail(path);
  const uint32_t total = static_cast<uint32_t>(scene.lights.size());
  ASSERT_GE(total, 2u);
  const std::vector<Camera> cameras = bookmark_cameras(path, {64, 48});
  ASSERT_FALSE(cameras.empty());
  const Camera& camera = cameras.front();
  for (const SkipOptions skip : {SkipOptions{}, SkipOptions::none()}) {
    VulkanTracer tracer(scene, vk_options(skip));
    VisibilityBuffer full;
    TraceStats full_stats;
    tracer.trace(camera, full, full_stats);
    const uint64_t hit = full_stats.pixels - full_stats.background_pixels;
    for (uint32_t n = 0; n <= total; ++n) {
      VisibilityBuffer subset;
      TraceStats stats;
      tracer.trace_lights(camera, n, subset, stats);
      ASSERT_EQ(subset.light_count, n);
      EXPECT_EQ(subset.mask_bits, mask_width_for_light_count(n));
      uint64_t differing = 0;
      for (size_t i = 0; i < full.pixel_count(); ++i)
        differing += subset.mask_at(i) != (full.mask_at(i) & subset.light_bits());
      EXPECT_EQ(differing, 0u) << n << " lights";
      EXPECT_EQ(stats.lights_unrequested, total - n);
      EXPECT_EQ(stats.shadow_rays + stats.skipped_backfacing + stats.skipped_out_of_range + stats.skipped_culled_light,
                hit * n);
      if (!skip.backfacing) {
        EXPECT_EQ(stats.shadow_rays, hit * n);
      }
    }
  }
}

// Single-sided quads seen from the back vanish for primary rays but still cast shadows; double-sided ones
// are seen from both sides; mirrored and plain instances of one geometry share a BLAS; lights are culled.
Scene make_instanced_scene() {
  Scene scene = test::make_empty_scene();
  add_grid(scene, {-6, 0, 6}, {12, 0, 0}, {0, 0, -12}, 6, test::kSingleSided);  // floor, facing up
  // One 1x1 quad geometry (local: x, y in [0, 1], facing +z), instanced four times.
  SceneMesh quad;
  quad.geometry = 100;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.normals.assign(4, glm::vec3(0, 0, 1));
  quad.indices = {0, 1, 2, 0, 2, 3};
  auto place = [&](const glm::dmat4& T, uint32_t material, const char* name) {
    SceneMesh m = quad;
    m.name = name;
    m.material = material;
    m.T_world_local = T;
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(T)));
    for (size_t v = 0; v < m.positions.size(); ++v) {
      m.positions[v] = glm::vec3(T * glm::dvec4(glm::dvec3(quad.positions[v]), 1.0));
      m.normals[v] = glm::vec3(glm::normalize(normal_matrix * glm::dvec3(quad.normals[v])));
    }
    if (glm::determinant(glm::dmat3(T)) < 0.0)  // the loader keeps world-space CCW fronts
      for (size_t t = 0; t < m.indices.size(); t += 3) std::swap(m.indices[t + 1], m.indices[t + 2]);
    scene.meshes.push_back(m);
  };
  const glm::dmat4 I(1.0);
  // Side by side along x (no overlaps): x in [-3.3, -2.3], [-1.8, -0.8], [0.2, 1.2], [1.8, 2.8], [2.3, 3.3].
  place(glm::translate(I, {-3.3, 0.5, 0.0}), test::kSingleSided, "front");  // faces the camera (+z)
  place(glm::rotate(glm::translate(I, {-0.8, 0.5, 0.0}), glm::pi<double>(), {0, 1, 0}), test::kSingleSided,
        "back");  // shows its back: invisible to primary rays, still casts a shadow
  place(glm::rotate(glm::translate(I, {1.2, 0.5, 0.0}), glm::pi<double>(), {0, 1, 0}), test::kDoubleSided,
        "double_back");
  place(glm::scale(glm::translate(I, {2.8, 0.5, 0.0}), {-1.0, 1.0, 1.0}), test::kSingleSided, "mirrored");
  place(glm::scale(glm::translate(I, {3.3, 0.5, -1.0}), {-1.0, 1.5, 1.0}), test::kSingleSided, "mirrored_2");
  scene.lights = {test::point_light({0.0f, 3.0f, 3.0f}, 20.0f), test::directional_light({0.3f, -1.0f, -0.4f}),
                  test::spot_light({-1.0f, 2.5f, -2.0f}, {0.2f, -1.0f, 0.5f}, 15.0f, 35.0f, 8.0f),
                  test::point_light({0.0f, 1.0f, 30.0f}, 5.0f, 1.0f)};  // behind the camera: culled
  finalize(scene);
  return scene;
}

TEST_F(VulkanTracerTest, InstancesMirroringAndDoubleSidedFacesMatchEmbree) {
  const Scene scene = make_instanced_scene();
  const std::vector<Camera> cameras = {test::look_camera({0.0, 2.0, 5.0}, {0.0, 0.5, 0.0}, 160, 120, 70.0),
                                       test::look_camera({1.0, 1.5, -4.0}, {0.0, 0.5, 0.0}, 160, 120, 70.0)};
  for (const bool instanced : {true, false}) {
    VulkanTracerConfig config;
    config.instanced = instanced;
    {
      VulkanTracer tracer(scene, vk_options(), config);
      EXPECT_EQ(tracer.accel_stats().instance_count, scene.meshes.size());
      // Instanced: floor, the shared quad (plain), the shared quad (mirrored).
      EXPECT_EQ(tracer.accel_stats().blas_count, instanced ? 3u : scene.meshes.size());
      EXPECT_EQ(tracer.accel_stats().triangles, scene.triangle_count);
      EXPECT_GT(tracer.accel_stats().bytes, 0u);
    }
    expect_agreement(scene, cameras, vk_options(), embree_options(), config);
  }
  VulkanTracer tracer(scene, vk_options());
  VisibilityBuffer vis;
  TraceStats stats;
  tracer.trace(cameras[0], vis, stats);
  EXPECT_EQ(stats.lights_culled, 1u);
}

TEST_F(VulkanTracerTest, MaskWidthsFollowTheLightCount) {
  const std::string path = test::source_path(kDefaultScenePath);
  Scene scene = load_scene_or_fail(path);
  ASSERT_FALSE(scene.lights.empty());
  const Camera camera = bookmark_cameras(path, {64, 48}).at(0);
  const std::vector<SceneLight> base = scene.lights;
  for (const uint32_t count : {9u, 17u, 32u}) {
    std::vector<SceneLight> lights;
    for (uint32_t i = 0; i < count; ++i) {
      SceneLight l = base[i % base.size()];
      l.position += glm::vec3(0.05f * float(i), 0.0f, -0.03f * float(i));
      lights.push_back(l);
    }
    ASSERT_FALSE(set_scene_lights(scene, lights));
    expect_agreement(scene, {camera}, vk_options(), embree_options());
  }
}

TEST_F(VulkanTracerTest, PreciseFarFromTheWorldOrigin) {
  const std::string path = test::source_path(kDefaultScenePath);
  Scene scene = load_scene_or_fail(path);
  const glm::dvec3 offset(25000.0, 120.0, -40000.0);
  for (SceneMesh& m : scene.meshes) {
    for (glm::vec3& p : m.positions) p = glm::vec3(glm::dvec3(p) + offset);
    m.T_world_local = glm::translate(glm::dmat4(1.0), offset) * m.T_world_local;
  }
  for (SceneLight& l : scene.lights) l.position = glm::vec3(glm::dvec3(l.position) + offset);
  finalize(scene);
  std::vector<Camera> cameras = bookmark_cameras(path, {96, 72});
  for (Camera& c : cameras) c.T_world_eye.position += offset;
  expect_agreement(scene, cameras, vk_options(), embree_options());
}

// A tilted, subdivided floor lit from 1-15 degrees above it, with nothing that could shadow it: every bit
// of every floor pixel must be 1 (no self-shadowing acne), near the origin and 3 km away. The far floor's
// vertices carry the offset themselves (identity node transform), so BLAS coordinates must be re-centred.
TEST_F(VulkanTracerTest, NoAcneAtGrazingLight) {
  const glm::dquat tilt = glm::angleAxis(glm::radians(23.0), glm::normalize(glm::dvec3(1.0, 0.3, 0.6)));
  for (const glm::dvec3& offset : {glm::dvec3(0.0, 1.3, 0.0), glm::dvec3(3000.0, 40.0, -2000.0)}) {
    auto to_world = [&](const glm::dvec3& p) { return glm::vec3(offset + tilt * p); };
    auto dir_to_world = [&](const glm::dvec3& d) { return glm::vec3(tilt * d); };
    Scene scene = test::make_empty_scene();
    add_grid(scene, to_world({-10, 0, 10}), dir_to_world({20, 0, 0}), dir_to_world({0, 0, -20}), 16,
             test::kSingleSided);
    for (int i = 0; i < 4; ++i) {
      const double e = glm::radians(std::array<double, 4>{1.0, 2.0, 5.0, 15.0}[size_t(i)]);
      const double a = glm::radians(20.0 + 90.0 * i);
      scene.lights.push_back(test::directional_light(
          glm::normalize(dir_to_world({-std::cos(e) * std::cos(a), -std::sin(e), -std::cos(e) * std::sin(a)}))));
    }
    SceneLight low = test::point_light(to_world({50.0, 0.9, 3.0}), 100.0f);
    scene.lights.push_back(low);
    finalize(scene);
    const Camera camera = test::look_camera(glm::dvec3(to_world({0.0, 3.0, 0.5})),
                                            glm::dvec3(to_world({0.0, 0.0, -1.5})), 96, 72, 100.0);
    VulkanTracer tracer(scene, vk_options());
    VisibilityBuffer vis;
    TraceStats stats;
    tracer.trace(camera, vis, stats);
    EXPECT_LT(stats.background_pixels, stats.pixels / 10);
    uint64_t unlit = 0;
    for (size_t i = 0; i < vis.pixel_count(); ++i)
      if (vis.mask_at(i) != 0) unlit += uint64_t(std::popcount(vis.light_bits() & ~vis.mask_at(i)));
    EXPECT_EQ(unlit, 0u) << "offset " << offset.x;
    EXPECT_EQ(stats.shadow_rays, (stats.pixels - stats.background_pixels) * scene.lights.size());
  }
}

TEST_F(VulkanTracerTest, EmptySceneAndBadInput) {
  Scene empty = test::make_empty_scene();
  empty.lights = {test::point_light({0, 1, 0}, 1.0f)};
  finalize(empty);
  VulkanTracer tracer(empty, vk_options());
  EXPECT_EQ(tracer.backend(), TracerBackend::kVulkan);
  EXPECT_FALSE(tracer.device_description().empty());
  const Camera camera = test::look_camera({0, 0, 3}, {0, 0, 0}, 32, 24);
  VisibilityBuffer vis;
  TraceStats stats;
  tracer.trace(camera, vis, stats);
  EXPECT_EQ(stats.background_pixels, stats.pixels);
  EXPECT_EQ(stats.primary_rays, stats.pixels);
  EXPECT_EQ(vis.width, 32u);
  EXPECT_TRUE(std::all_of(vis.data.begin(), vis.data.end(), [](uint8_t b) { return b == 0; }));

  Camera bad = camera;
  bad.extent = {0, 24};
  EXPECT_THROW(tracer.trace(bad, vis, stats), std::invalid_argument);

  Scene too_many = empty;
  too_many.lights.assign(kMaxSlotLights + 1, test::point_light({0, 1, 0}, 1.0f));
  EXPECT_THROW(VulkanTracer(too_many, vk_options()), std::runtime_error);

  Scene broken = empty;
  add_grid(broken, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, test::kSingleSided);
  broken.meshes.back().indices[2] = 99;
  EXPECT_THROW(VulkanTracer(broken, vk_options()), std::runtime_error);

  TracerOptions bad_device = vk_options();
  bad_device.vk_device = "quantum";
  EXPECT_THROW(VulkanTracer(empty, bad_device), std::runtime_error);
}

TEST(VulkanTracerPlan, MortonOrderIsADeterministicSpatialPermutation) {
  // A 32x32 grid's triangles in shuffled order: the Morton order must visit them with short steps.
  Scene scene = test::make_empty_scene();
  add_grid(scene, {0, 0, 0}, {32, 0, 0}, {0, 32, 0}, 32, test::kSingleSided);
  SceneMesh& mesh = scene.meshes[0];
  std::vector<uint32_t> tris(mesh.triangle_count());
  for (uint32_t t = 0; t < tris.size(); ++t) tris[t] = t;
  std::mt19937 rng(7);
  std::shuffle(tris.begin(), tris.end(), rng);
  std::vector<uint32_t> shuffled;
  for (uint32_t t : tris) shuffled.insert(shuffled.end(), &mesh.indices[3 * t], &mesh.indices[3 * t] + 3);
  std::vector<float> xyz;
  for (const glm::vec3& p : mesh.positions) xyz.insert(xyz.end(), {p.x, p.y, p.z});

  const std::vector<uint32_t> order = detail::morton_triangle_order(xyz, shuffled);
  EXPECT_EQ(order, detail::morton_triangle_order(xyz, shuffled));
  std::vector<uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
  auto centroid = [&](uint32_t t) {
    return (mesh.positions[shuffled[3 * t]] + mesh.positions[shuffled[3 * t + 1]] +
            mesh.positions[shuffled[3 * t + 2]]) / 3.0f;
  };
  double sorted_path = 0.0, shuffled_path = 0.0;
  for (size_t i = 1; i < order.size(); ++i) {
    sorted_path += double(glm::length(centroid(order[i]) - centroid(order[i - 1])));
    shuffled_path += double(glm::length(centroid(uint32_t(i)) - centroid(uint32_t(i - 1))));
  }
  EXPECT_LT(sorted_path, 2.0 * double(order.size()));  // ~1 cell per step
  EXPECT_LT(sorted_path * 5.0, shuffled_path);

  // The plan maps every BLAS primitive back to the original triangle.
  mesh.indices = shuffled;
  finalize(scene);
  const detail::ScenePlan plan = detail::plan_gpu_scene(scene, VulkanTracerConfig{});
  ASSERT_EQ(plan.blases.size(), 1u);
  const detail::BlasPlan& blas = plan.blases[0];
  for (uint32_t p = 0; p < tris.size(); ++p) {
    const uint32_t original = plan.permutation[blas.permutation_offset + p];
    for (uint32_t k = 0; k < 3; ++k) ASSERT_EQ(blas.indices[3 * p + k], shuffled[3 * original + k]);
  }
}

// The agreement's failure text for a pixel-light bit: a lit bit's shadow ray meets no front face before the light;
// some shadowed bit's meets its occluder, named with its barycentrics.
// The one bit the H100 disagreed on (2026-11-27): MaskWidthsFollowTheLightCount's light 30 sits on a face of the
// default room, and the reference's shadow ray from pixel (64, 32) met that face at the light's distance. Embree
// alone: that bit is a light on a surface, and a light in free space is not.
TEST(VulkanTracerAgreement, ExplainsALightOnASurface) {
  const std::string path = test::source_path(kDefaultScenePath);
  Scene scene = load_scene_or_fail(path);
  const Camera camera = bookmark_cameras(path, {64, 48}).at(0);
  SceneLight on_face = scene.lights[30 % scene.lights.size()];
  on_face.position += glm::vec3(0.05f * 30.0f, 0.0f, -0.03f * 30.0f);
  TracerOptions options;
  options.threads = 2;
  EmbreeTracer embree(scene, options);
  EXPECT_TRUE(occluder_at_the_light(embree.embree_scene(), camera, on_face, 64, 32))
      << describe_shadow_rays(embree, camera, {on_face}, 64, 32, 1u);
  size_t at_light = 0, met = 0;
  for (const SceneLight& light : scene.lights) {  // the scene's own lights hang in free space
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x) {
        at_light += occluder_at_the_light(embree.embree_scene(), camera, light, x, y);
        met += describe_shadow_rays(embree, camera, {light}, x, y, 1u).find("meets mesh") != std::string::npos;
      }
  }
  EXPECT_EQ(at_light, 0u);
  EXPECT_GT(met, 10u);  // shadowed pixels exist, and none of them is "at the light"
}

TEST(VulkanTracerAgreement, DescribesWhereAShadowRayMeetsItsOccluder) {
  const std::string path = test::source_path(kDefaultScenePath);
  const Scene scene = load_scene_or_fail(path);
  const Camera camera = bookmark_cameras(path, {64, 48}).at(0);
  TracerOptions options;
  options.threads = 2;
  options.skip = SkipOptions::none();  // every hit pixel's bit is its shadow ray's
  EmbreeTracer embree(scene, options);
  VisibilityBuffer vis;
  TraceStats stats;
  embree.trace(camera, vis, stats);
  size_t lit = 0, met = 0;
  for (uint32_t y = 0; y < camera.extent.height; ++y) {
    for (uint32_t x = 0; x < camera.extent.width; ++x) {
      for (uint32_t li = 0; li < vis.light_count; ++li) {
        const std::string text = describe_shadow_rays(embree, camera, scene.lights, int(x), int(y), 1u << li);
        if (text.find("no primary hit") != std::string::npos) continue;
        if ((vis.get(x, y) >> li) & 1u) {
          ++lit;
          EXPECT_NE(text.find("no front face before the light"), std::string::npos) << x << "," << y << ": " << text;
        } else if (text.find("meets mesh") != std::string::npos) {
          EXPECT_NE(text.find("barycentrics"), std::string::npos) << text;
          ++met;
        }
      }
    }
  }
  EXPECT_GT(lit, 100u);
  EXPECT_GT(met, 10u);
}

}  // namespace
}  // namespace dhr::server
