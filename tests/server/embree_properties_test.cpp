// Properties of the Embree tracer: skipping and culling never change a bit, output independent of thread
// count and repetition, no shadow acne at grazing light, precision far from the world origin, mask width.
#include "scene/camera_bookmarks.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <bit>
#include <cmath>

namespace dhr::server {
namespace {

using test::add_box;
using test::add_grid;
using test::finalize;

TracerOptions options_with(SkipOptions skip, uint32_t threads = 2) {
  TracerOptions o;
  o.skip = skip;
  o.threads = threads;
  return o;
}

using test::differing_pixels;

using test::bookmark_cameras;

// Skipping (N.L, range, culling) against SkipOptions::none(): identical bits, and the counters add up.
void expect_skipping_changes_nothing(const Scene& scene, const std::vector<Camera>& cameras) {
  EmbreeTracer skipping(scene, options_with(SkipOptions{}));
  EmbreeTracer exhaustive(scene, options_with(SkipOptions::none()));
  for (size_t c = 0; c < cameras.size(); ++c) {
    VisibilityBuffer a, b;
    TraceStats sa, sb;
    skipping.trace(cameras[c], a, sa);
    exhaustive.trace(cameras[c], b, sb);
    EXPECT_EQ(differing_pixels(a, b), 0u) << "camera " << c;
    const uint64_t hit = sa.pixels - sa.background_pixels;
    EXPECT_EQ(sb.background_pixels, sa.background_pixels);
    EXPECT_EQ(sb.shadow_rays, hit * scene.lights.size());
    EXPECT_EQ(sa.shadow_rays + sa.skipped_backfacing + sa.skipped_out_of_range + sa.skipped_culled_light,
              hit * scene.lights.size());
    EXPECT_LE(sa.shadow_rays, sb.shadow_rays);
  }
}

TEST(EmbreeProperties, SkippingChangesNoBitOnTheDefaultScene) {
  const std::string path = test::source_path(kDefaultScenePath);
  SceneLoadResult loaded = load_scene(path);
  ASSERT_TRUE(loaded) << loaded.error;
  const auto cameras = bookmark_cameras(path, {160, 120});
  ASSERT_FALSE(cameras.empty());
  expect_skipping_changes_nothing(*loaded.scene, cameras);
}

TEST(EmbreeProperties, SkippingChangesNoBitOnTheLivingRoom) {
  const std::string path = test::shared_data_path("scenes/living_room.glb");
  if (path.empty()) GTEST_SKIP() << "../shared/data not present";
  SceneLoadResult loaded = load_scene(path);
  ASSERT_TRUE(loaded) << loaded.error;
  const auto cameras = bookmark_cameras(path, {160, 120});
  ASSERT_EQ(cameras.size(), 5u);
  expect_skipping_changes_nothing(*loaded.scene, cameras);
}

// A 4x4 block with few pixels left to trace (reuse took the others, or the image's edge cuts it) traces them one ray
// at a time instead of as a packet: both must give the same bits. Here every block is traced each way (the
// configuration's single rays) at a size whose edge blocks hold 1 to 3 lanes.
TEST(EmbreeProperties, SingleRaysAndPacketsGiveTheSameBits) {
  const std::string paths[] = {test::source_path(kDefaultScenePath), test::shared_data_path("scenes/living_room.glb")};
  for (const std::string& path : paths) {
    if (path.empty()) continue;  // ../shared/data not present: the default room alone
    SCOPED_TRACE(path);
    SceneLoadResult loaded = load_scene(path);
    ASSERT_TRUE(loaded) << loaded.error;
    EmbreeTracerConfig singles;
    singles.primary_packets = false;
    EmbreeTracer packets(*loaded.scene, options_with(SkipOptions{}));
    EmbreeTracer single(*loaded.scene, options_with(SkipOptions{}), singles);
    for (const Camera& camera : bookmark_cameras(path, {161, 122})) {
      VisibilityBuffer a, b;
      TraceStats sa, sb;
      packets.trace(camera, a, sa);
      single.trace(camera, b, sb);
      EXPECT_EQ(differing_pixels(a, b), 0u);
      EXPECT_EQ(sa.background_pixels, sb.background_pixels);
    }
  }
}

TEST(EmbreeProperties, CullingLightsOutsideTheViewChangesNoBit) {
  Scene scene = test::make_empty_scene();
  add_grid(scene, {-10, 0, 10}, {20, 0, 0}, {0, 0, -20}, 8, test::kSingleSided);
  add_box(scene, {-0.5f, 0.5f, -0.5f}, {0.5f, 1.5f, 0.5f}, test::kSingleSided);
  scene.lights = {
      test::point_light({0.0f, 1.0f, 9.0f}, 10.0f, 2.0f),   // behind the camera, small range: culled
      test::point_light({0.0f, 2.5f, 0.0f}, 10.0f, 6.0f),   // in view
      test::spot_light({15.0f, 1.0f, 0.0f}, {0, -1, 0}, 10.0f, 20.0f, 1.0f),  // far right, out of the frustum
      test::directional_light({0.2f, -1.0f, 0.1f}),          // never culled
  };
  finalize(scene);
  const Camera camera = test::look_camera({0.0, 2.0, 5.0}, {0.0, 0.5, 0.0}, 160, 120, 60.0);
  EmbreeTracer culling(scene, options_with(SkipOptions{}));
  EmbreeTracer plain(scene, options_with(SkipOptions::none()));
  VisibilityBuffer a, b;
  TraceStats sa, sb;
  culling.trace(camera, a, sa);
  plain.trace(camera, b, sb);
  EXPECT_EQ(sa.lights_culled, 2u);
  EXPECT_EQ(sb.lights_culled, 0u);
  EXPECT_EQ(sa.skipped_culled_light, 2 * (sa.pixels - sa.background_pixels));
  EXPECT_EQ(differing_pixels(a, b), 0u);
  // The in-view lights do light something.
  uint32_t any = 0;
  for (size_t i = 0; i < a.pixel_count(); ++i) any |= a.mask_at(i);
  EXPECT_EQ(any, 0b1010u);
}

TEST(EmbreeProperties, SameOutputForAnyThreadCountAndRepetition) {
  std::string path = test::shared_data_path("scenes/living_room.glb");
  if (path.empty()) path = test::source_path(kDefaultScenePath);
  SceneLoadResult loaded = load_scene(path);
  ASSERT_TRUE(loaded) << loaded.error;
  const Camera camera = bookmark_cameras(path, {200, 150}).at(0);
  EmbreeTracer one(*loaded.scene, options_with(SkipOptions{}, 1));
  EmbreeTracer two(*loaded.scene, options_with(SkipOptions{}, 2));
  VisibilityBuffer a, b, c;
  TraceStats sa, sb, sc;
  one.trace(camera, a, sa);
  two.trace(camera, b, sb);
  two.trace(camera, c, sc);
  EXPECT_EQ(differing_pixels(a, b), 0u);
  EXPECT_EQ(differing_pixels(b, c), 0u);
  EXPECT_EQ(sa.shadow_rays, sb.shadow_rays);
  EXPECT_EQ(sa.skipped_backfacing, sb.skipped_backfacing);
  EXPECT_EQ(sb.shadow_rays, sc.shadow_rays);
}

uint64_t popcount_missing(uint32_t mask, uint32_t all) { return static_cast<uint64_t>(std::popcount(all & ~mask)); }

// A subdivided floor lit from low angles with nothing to cast a shadow: every floor pixel must be lit.
// A subdivided floor (rotated by `rotation`, moved by `offset`) lit from low angles with nothing to cast a
// shadow on it: every light bit of every floor pixel must be 1.
uint64_t unlit_floor_pixels(const glm::dvec3& offset, const glm::dquat& rotation,
                            const std::vector<SceneLight>& lights_in_floor_frame) {
  auto to_world = [&](const glm::dvec3& p) { return glm::vec3(offset + rotation * p); };
  auto dir_to_world = [&](const glm::dvec3& d) { return glm::vec3(rotation * d); };
  Scene scene = test::make_empty_scene();
  add_grid(scene, to_world({-10, 0, 10}), dir_to_world({20, 0, 0}), dir_to_world({0, 0, -20}), 16, test::kSingleSided);
  // A quad far below the floor (it cannot occlude rays leaving the floor upward) moves the bounding-box
  // centre, so the floor is not at relative height 0 and the ULP-scaled offset path is exercised.
  add_grid(scene, to_world({-1, -20, -1}), dir_to_world({2, 0, 0}), dir_to_world({0, 0, 2}), 1, test::kSingleSided);
  for (SceneLight l : lights_in_floor_frame) {
    l.position = to_world(glm::dvec3(l.position));
    l.direction = glm::normalize(dir_to_world(glm::dvec3(l.direction)));
    scene.lights.push_back(l);
  }
  finalize(scene);
  EmbreeTracer tracer(scene, options_with(SkipOptions{}));
  const Camera camera = test::look_camera(glm::dvec3(to_world({0.0, 3.0, 0.5})), glm::dvec3(to_world({0.0, 0.0, -1.5})),
                                          200, 150, 100.0);
  VisibilityBuffer vis;
  TraceStats stats;
  tracer.trace(camera, vis, stats);
  EXPECT_LT(stats.background_pixels, stats.pixels / 10);
  uint64_t unlit = 0;
  const uint32_t all = vis.light_bits();
  const glm::dvec3 n = rotation * glm::dvec3(0, 1, 0), o = camera.T_world_eye.position;
  for (size_t i = 0; i < vis.pixel_count(); ++i) {
    const uint32_t x = static_cast<uint32_t>(i % vis.width), y = static_cast<uint32_t>(i / vis.width);
    const glm::dvec3 d = camera.world_ray(x + 0.5, y + 0.5);
    if (!(glm::dot(d, n) < 0.0)) continue;
    const glm::dvec3 p = o + d * (glm::dot(offset - o, n) / glm::dot(d, n));
    const glm::dvec3 local = glm::conjugate(rotation) * (p - offset);
    if (std::fabs(local.x) > 9.9 || std::fabs(local.z) > 9.9) continue;  // away from the floor's edge
    unlit += popcount_missing(vis.mask_at(i), all);
  }
  return unlit;
}

std::vector<SceneLight> grazing_lights() {
  std::vector<SceneLight> lights;
  // Directional lights 1, 2, 5, 15 degrees above the horizon, from four azimuths.
  const float elevations[] = {1.0f, 2.0f, 5.0f, 15.0f};
  for (int i = 0; i < 4; ++i) {
    const float e = glm::radians(elevations[i]), a = glm::radians(20.0f + 90.0f * static_cast<float>(i));
    lights.push_back(test::directional_light({-std::cos(e) * std::cos(a), -std::sin(e), -std::cos(e) * std::sin(a)}));
  }
  // Point lights low and far: about 1 degree above the floor at 40-60 m.
  lights.push_back(test::point_light({50.0f, 0.9f, 3.0f}, 100.0f));
  lights.push_back(test::point_light({-2.0f, 0.7f, -45.0f}, 100.0f));
  return lights;
}

const glm::dquat kNoRotation(1.0, 0.0, 0.0, 0.0);
// Tilted so that every coordinate of a floor point carries rounding error.
const glm::dquat kTilt = glm::angleAxis(glm::radians(23.0), glm::normalize(glm::dvec3(1.0, 0.3, 0.6)));

TEST(EmbreeProperties, NoAcneAtGrazingLight) {
  EXPECT_EQ(unlit_floor_pixels(glm::dvec3(0.0), kNoRotation, grazing_lights()), 0u);
  EXPECT_EQ(unlit_floor_pixels(glm::dvec3(0.0, 1.3, 0.0), kTilt, grazing_lights()), 0u);
}

TEST(EmbreeProperties, NoAcneFarFromTheWorldOrigin) {
  // 3 km away: the scene is traced relative to its bounding-box centre, so this is as exact as near 0.
  EXPECT_EQ(unlit_floor_pixels(glm::dvec3(3000.0, 120.0, -2000.0), kNoRotation, grazing_lights()), 0u);
  EXPECT_EQ(unlit_floor_pixels(glm::dvec3(3000.0, 120.0, -2000.0), kTilt, grazing_lights()), 0u);
}

TEST(EmbreeProperties, MaskWidthFollowsLightCount) {
  Scene scene = test::make_empty_scene();
  add_grid(scene, {-10, 0, 10}, {20, 0, 0}, {0, 0, -20}, 2, test::kSingleSided);
  for (int i = 0; i < 9; ++i) scene.lights.push_back(test::point_light({static_cast<float>(i) - 4.0f, 2.0f, 0.0f}, 5.0f));
  finalize(scene);
  EmbreeTracer tracer(scene, options_with(SkipOptions{}));
  EXPECT_EQ(tracer.light_count(), 9u);
  VisibilityBuffer vis;
  TraceStats stats;
  tracer.trace(test::look_camera({0.0, 4.0, 4.0}, {0.0, 0.0, 0.0}, 32, 24), vis, stats);
  EXPECT_EQ(vis.mask_bits, MaskWidth::k16);
  EXPECT_EQ(vis.get(16, 12), 0x1FFu);  // nothing occludes: every light reaches the floor below the camera
}

TEST(EmbreeProperties, RejectsAnUnusableCamera) {
  Scene scene = test::make_empty_scene();
  add_grid(scene, {-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, 1, test::kSingleSided);
  finalize(scene);
  EmbreeTracer tracer(scene, options_with(SkipOptions{}));
  Camera camera = test::look_camera({0.0, 1.0, 1.0}, {0.0, 0.0, 0.0}, 16, 16);
  camera.extent = Extent{0, 16};
  VisibilityBuffer vis;
  TraceStats stats;
  EXPECT_THROW(tracer.trace(camera, vis, stats), std::invalid_argument);
  camera.extent = Extent{16, 16};
  camera.T_world_eye.position.x = std::nan("");
  EXPECT_THROW(tracer.trace(camera, vis, stats), std::invalid_argument);
}

TEST(EmbreeProperties, AccelStatsDescribeTheBuild) {
  Scene scene = test::make_empty_scene();
  add_grid(scene, {-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, 4, test::kSingleSided);
  add_box(scene, {0, 0, 0}, {1, 1, 1}, test::kDoubleSided);
  finalize(scene);
  EmbreeTracer tracer(scene, options_with(SkipOptions{}));
  const AccelStats& s = tracer.accel_stats();
  EXPECT_EQ(s.triangles, 32u + 12u);
  EXPECT_EQ(s.blas_count, 7u);
  EXPECT_GT(s.bytes, 0u);
  EXPECT_GE(s.build_ms, 0.0);
  EXPECT_NE(tracer.device_description().find("Embree"), std::string::npos);
}

}  // namespace
}  // namespace dhr::server
