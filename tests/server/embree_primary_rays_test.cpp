// The Embree tracer's primary rays come from per-frame column/row tables (embree_trace_tile.hpp): they must be
// bit-identical to the camera maths they replace, normalize(R * camera.eye_ray(x + 0.5, y + 0.5)) in double.
// They start at the client's near plane: what the client's rasterizer clips is not traced in its place.
#include "trace/embree/embree_scene.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "trace/embree/embree_trace_tile.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>

#include <bit>
#include <random>

namespace dhr::server {
namespace {

glm::vec3 reference_direction(const Camera& camera, uint32_t x, uint32_t y) {
  const glm::dmat3 R = glm::mat3_cast(glm::normalize(camera.T_world_eye.orientation));
  return glm::vec3(glm::normalize(R * camera.eye_ray(x + 0.5, y + 0.5)));
}

TEST(EmbreePrimaryRays, TablesGiveTheCameraMathsBitForBit) {
  Scene scene = test::make_empty_scene();
  test::add_grid(scene, {-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, 1, test::kSingleSided);
  test::finalize(scene);
  const auto embree = EmbreeScene::create(scene);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> angle(0.05f, 1.4f);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int c = 0; c < 12; ++c) {
    View view;
    view.fov = Fov{-angle(rng), angle(rng), angle(rng), -angle(rng)};  // asymmetric
    view.pose.position = glm::dvec3(unit(rng), unit(rng), unit(rng)) * (c < 6 ? 3.0 : 1e5);
    view.pose.orientation = glm::normalize(glm::dquat(unit(rng), unit(rng), unit(rng), unit(rng)));
    const Extent eye{61u + 7u * uint32_t(c), 37u + 5u * uint32_t(c)};  // odd sizes
    const Camera camera = Camera::with_guard_band(view, eye, GuardBand{uint32_t(c) * 3u, uint32_t(c)});
    const detail::FrameSetup frame = detail::make_frame_setup(*embree, scene.lights, camera, SkipOptions{});
    uint64_t differing = 0;
    for (uint32_t y = 0; y < camera.extent.height; ++y) {
      for (uint32_t x = 0; x < camera.extent.width; ++x) {
        const glm::vec3 got = detail::primary_direction(frame, x, y), want = reference_direction(camera, x, y);
        for (int i = 0; i < 3; ++i) differing += std::bit_cast<uint32_t>(got[i]) != std::bit_cast<uint32_t>(want[i]);
      }
    }
    EXPECT_EQ(differing, 0u) << "camera " << c;
  }
}

// A wall in front of the eye, nearer than the near plane (kClipNearPlane along the view axis) in one run and
// just beyond it in the other: the first is not traced (every pixel background, as the client's rasterizer
// clips it), the second is.
TEST(EmbreePrimaryRays, StartAtTheClientsNearPlane) {
  for (const double distance : {0.6 * kClipNearPlane, 1.4 * kClipNearPlane}) {
    SCOPED_TRACE(distance);
    Scene scene = test::make_empty_scene();
    // Facing +Z (toward the eye at the origin looking along -Z), 4 m wide: fills the view.
    const float z = static_cast<float>(-distance);
    test::add_grid(scene, {-2.0f, -2.0f, z}, {4.0f, 0.0f, 0.0f}, {0.0f, 4.0f, 0.0f}, 2, test::kSingleSided);
    scene.lights.push_back(test::point_light({0.0f, 0.0f, 1.0f}, 5.0f));
    test::finalize(scene);
    const Camera camera = test::look_camera({0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 32, 24, 60.0);
    EmbreeTracer tracer(scene, TracerOptions{});
    VisibilityBuffer out;
    TraceStats stats;
    tracer.trace(camera, out, stats);
    const uint64_t pixels = uint64_t{camera.extent.width} * camera.extent.height;
    EXPECT_EQ(stats.background_pixels, distance < kClipNearPlane ? pixels : 0u);
  }
}

}  // namespace
}  // namespace dhr::server
