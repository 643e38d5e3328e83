// Degenerate geometry (zero-area and sliver triangles, duplicate vertices, coplanar overlapping faces), the
// 1.2M-triangle dense living room, and determinism: no crash, bounded memory, the same bits every run.
#include "trace/embree/embree_tracer.hpp"
#include "stress_support.hpp"
#include "test_scenes.hpp"
#include "trace/vulkan/vulkan_tracer.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace dhr::stress {
namespace {

using server::TracerBackend;

SceneMesh triangles(const char* name, std::vector<glm::vec3> positions, uint32_t material) {
  SceneMesh m;
  m.name = name;
  m.material = material;
  m.positions = std::move(positions);
  m.normals.assign(m.positions.size(), glm::vec3(0.0f, 1.0f, 0.0f));
  for (uint32_t i = 0; i < m.positions.size(); ++i) m.indices.push_back(i);
  return m;
}

// Lit floor (y = 0) carrying, on x < 2.5, coplanar overlapping quads, zero-area and sliver triangles in its
// plane and an unwelded copy of itself (every vertex duplicated); above x in [3, 5], slivers and
// degenerate triangles in the air. Lights straight above: every floor pixel with x < 2.5 must be lit.
Scene degenerate_scene() {
  Scene scene = test::make_empty_scene();
  test::add_grid(scene, {-5, 0, 5}, {10, 0, 0}, {0, 0, -10}, 10, test::kSingleSided);
  // Coplanar overlapping faces: two more grids in the floor plane, one double-sided, offset and finer.
  test::add_grid(scene, {-3, 0, 2}, {4, 0, 0}, {0, 0, -4}, 7, test::kDoubleSided);
  test::add_grid(scene, {-2.5f, 0, 1.5f}, {3, 0, 0}, {0, 0, -3}, 3, test::kSingleSided);
  // Zero-area (repeated and collinear vertices) and slivers (1e-7 m wide) in the floor plane.
  scene.meshes.push_back(triangles("degenerate_floor",
                                   {{0, 0, 0}, {0, 0, 0}, {0, 0, 0},                 // a point
                                    {-1, 0, 1}, {0, 0, 1}, {1, 0, 1},                // collinear
                                    {-2, 0, -1}, {2, 0, -1}, {-2, 0, -1.0000001f},   // sliver
                                    {-1, 0, -2}, {-1.0000001f, 0, -2}, {-1, 0, 2}},  // needle
                                   test::kSingleSided));
  // Duplicate vertices: the floor's left half again, every triangle with its own three vertices.
  {
    const SceneMesh& floor = scene.meshes[0];
    std::vector<glm::vec3> soup;
    for (uint32_t idx : floor.indices)
      if (floor.positions[idx].x <= 2.0f) soup.push_back(floor.positions[idx]);
    soup.resize(soup.size() / 3 * 3);
    scene.meshes.push_back(triangles("unwelded_floor", soup, test::kSingleSided));
  }
  // In the air above x in [3, 5]: slivers, zero-area triangles and a coplanar-overlapping pair of quads.
  scene.meshes.push_back(triangles("degenerate_air",
                                   {{3, 1, 0}, {5, 1, 0}, {3, 1, 1e-7f},           // sliver
                                    {4, 1.5f, 1}, {4, 1.5f, 1}, {4, 1.5f, 1},      // a point
                                    {3, 0.5f, -1}, {4, 0.5f, -1}, {5, 0.5f, -1}},  // collinear
                                   test::kSingleSided));
  test::add_grid(scene, {3, 2, 1}, {1.5f, 0, 0}, {0, 0, -1.5f}, 1, test::kSingleSided);
  test::add_grid(scene, {3.5f, 2, 0.5f}, {1.5f, 0, 0}, {0, 0, -1.5f}, 2, test::kDoubleSided);
  scene.lights = {test::directional_light({0.0f, -1.0f, 0.0f}), test::point_light({-1.0f, 6.0f, 0.5f}, 50.0f),
                  test::directional_light(glm::normalize(glm::vec3(0.3f, -1.0f, -0.2f)))};
  test::finalize(scene);
  return scene;
}

void run_degenerate(TracerBackend backend, Extent size) {
  const Scene scene = degenerate_scene();
  const Camera camera = test::look_camera({-1.0, 6.0, 6.0}, {0.5, 0.0, 0.0}, size.width, size.height, 80.0);
  auto tracer = server::create_tracer(backend, scene,
                                      backend == TracerBackend::kEmbree ? embree_options() : vulkan_options());
  VisibilityBuffer first, again;
  server::TraceStats stats;
  tracer->trace(camera, first, stats);
  tracer->trace(camera, again, stats);
  const VisibilityBuffer fresh = trace_once(backend, scene, camera);
  EXPECT_EQ(differing_bits(first, again), 0u);
  EXPECT_EQ(differing_bits(first, fresh), 0u);
  // Floor pixels on x < 2.4 (nothing above them): all lit.
  uint64_t pairs = 0, acne = 0;
  const glm::dvec3 o = camera.T_world_eye.position;
  for (size_t i = 0; i < first.pixel_count(); ++i) {
    const glm::dvec3 d = camera.world_ray(double(i % first.width) + 0.5, double(i / first.width) + 0.5);
    if (!(d.y < 0.0)) continue;
    const glm::dvec3 p = o + d * (-o.y / d.y);
    if (p.x > 2.4 || p.x < -4.9 || std::fabs(p.z) > 4.9) continue;
    pairs += first.light_count;
    acne += uint64_t(std::popcount(first.light_bits() & ~first.mask_at(i)));
  }
  ASSERT_GT(pairs, 100u);
  const double rate = double(acne) / double(pairs);
  const std::string name = std::string("degenerate_geometry_") + backend_label(backend);
  report(name, "acne_rate", rate, 1e-4);
  report(name, "nondeterministic_bits", double(differing_bits(first, again) + differing_bits(first, fresh)), 0.0);
  EXPECT_LE(rate, 1e-4);
}

TEST(StressGeometry, EmbreeDegenerateTrianglesAndCoplanarFaces) {
  run_degenerate(TracerBackend::kEmbree, pick(Extent{128, 96}, Extent{320, 240}));
}

TEST(StressGeometry, VulkanDegenerateTrianglesAndCoplanarFaces) {
  run_degenerate(TracerBackend::kVulkan, pick(Extent{48, 36}, Extent{128, 96}));
}

// The dense living room (1.2M triangles): loads, builds and traces within a memory bound, and twice gives
// the same bits (also against a second tracer instance with another thread count).
TEST(StressGeometry, DenseLivingRoomIsBoundedAndDeterministic) {
  const std::string path = test::shared_data_path("scenes/living_room_dense.glb");
  if (path.empty()) GTEST_SKIP() << "../shared/data not present: living_room_dense.glb skipped";
  const auto start = std::chrono::steady_clock::now();
  const Scene scene = load_scene_or_fail(path);
  ASSERT_GT(scene.triangle_count, 1'000'000u);
  const double load_rss = peak_rss_mib();
  const std::vector<Camera> cameras = bookmark_cameras(path, pick(Extent{48, 36}, Extent{160, 120}));
  ASSERT_FALSE(cameras.empty());
  server::EmbreeTracer a(scene, embree_options());
  server::TracerOptions one_thread = embree_options();
  one_thread.threads = 1;
  server::EmbreeTracer b(scene, one_thread);
  uint64_t differing = 0, lit = 0;
  for (const Camera& c : cameras) {
    VisibilityBuffer v1, v2, v3;
    server::TraceStats s;
    a.trace(c, v1, s);
    a.trace(c, v2, s);
    b.trace(c, v3, s);
    differing += differing_bits(v1, v2) + differing_bits(v1, v3);
    for (size_t i = 0; i < v1.pixel_count(); ++i) lit += uint64_t(std::popcount(v1.mask_at(i)));
  }
  {  // Vulkan (lavapipe: a few seconds for the 1.2M-triangle BLAS), one camera at a tiny size
    server::VulkanTracer vk(scene, vulkan_options());
    const Camera small = bookmark_cameras(path, pick(Extent{24, 18}, Extent{96, 72})).at(0);
    VisibilityBuffer v1, v2;
    server::TraceStats s;
    vk.trace(small, v1, s);
    vk.trace(small, v2, s);
    differing += differing_bits(v1, v2);
  }
  const double peak = peak_rss_mib();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Bound: 1.2M triangles as float positions + normals + indices is ~60 MB per copy; the loader, the Scene,
  // Embree's BVH (x2 tracers) and glTF buffers stay well under 3 GiB.
  constexpr double kRssBoundMib = 3072.0;
  report("dense_living_room", "peak_rss_mib", peak, kRssBoundMib);
  report("dense_living_room", "nondeterministic_bits", double(differing), 0.0);
  std::printf("[stress] dense_living_room: %llu triangles, rss after load %.0f MiB, %.1f s\n",
              static_cast<unsigned long long>(scene.triangle_count), load_rss, seconds);
  EXPECT_LE(peak, kRssBoundMib);
  EXPECT_EQ(differing, 0u);
  EXPECT_GT(lit, 0u);
}

// Scenes near the float limits get a finite default light rig (shared/scene/src/scene_lights.cpp computed the
// rig in float: its size and intensity overflowed to inf for coordinates beyond ~1e19).
TEST(StressGeometry, HugeCoordinatesGetAFiniteDefaultLightRig) {
  uint64_t invalid = 0;
  for (const float extent : {1e3f, 1e10f, 1e19f, 1e20f, 1e30f, 3e38f}) {
    SceneBounds bounds;
    bounds.extend(glm::vec3(-extent, 0.0f, -extent));
    bounds.extend(glm::vec3(extent, extent, extent));
    for (const SceneLight& light : make_default_light_rig(bounds)) {
      const auto error = validate_light(light);
      EXPECT_FALSE(error.has_value()) << extent << ": " << error.value_or("");
      invalid += error.has_value();
    }
  }
  report("default_light_rig_huge_coordinates", "invalid_lights", double(invalid), 0.0);
}

// The same run twice gives the same bits: Embree on the living room (or the default room), Vulkan on the
// default room, each time with a fresh tracer.
TEST(StressDeterminism, SameRunTwiceGivesTheSameBits) {
  std::string path = test::shared_data_path("scenes/living_room.glb");
  if (path.empty()) path = test::source_path(kDefaultScenePath);
  const Scene scene = load_scene_or_fail(path);
  uint64_t differing = 0;
  for (const Camera& c : bookmark_cameras(path, pick(Extent{64, 48}, Extent{192, 144}))) {
    differing += differing_bits(trace_once(TracerBackend::kEmbree, scene, c), trace_once(TracerBackend::kEmbree, scene, c));
  }
  const std::string room = test::source_path(kDefaultScenePath);
  const Scene small = load_scene_or_fail(room);
  const Camera camera = bookmark_cameras(room, pick(Extent{32, 24}, Extent{96, 72})).at(0);
  differing += differing_bits(trace_once(TracerBackend::kVulkan, small, camera),
                              trace_once(TracerBackend::kVulkan, small, camera));
  report("determinism_tracers", "differing_bits", double(differing), 0.0);
  EXPECT_EQ(differing, 0u);
}

}  // namespace
}  // namespace dhr::stress
