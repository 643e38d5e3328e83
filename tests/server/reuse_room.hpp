// The reuse tests' scene and cameras (tests/server): a room with a floor, a back wall, a box and two point lights,
// optionally a box and a light on an animated node, and the bound on differing bits.
#pragma once
#include "scene/scene.hpp"
#include "test_animated_scene.hpp"
#include "test_scenes.hpp"
#include "trace/embree/embree_tracer.hpp"

#include <cstdint>

namespace dhr::server::reuse_test {

inline constexpr double kMaxDifferingShare = 1e-4;  // the bound on differing pixel-light bits
inline constexpr uint32_t kMovingNode = 5;

inline TracerOptions threads(uint32_t n) {
  TracerOptions o;
  o.threads = n;
  return o;
}

// A floor, a back wall, a static box (shadow caster) and two point lights; optionally a box on an animated node
// (slides 2 m along +x in 2 s) and a light on it.
inline Scene room(bool moving_box, bool moving_light) {
  Scene s = test::make_empty_scene();
  test::add_grid(s, glm::vec3(-4, 0, -4), glm::vec3(0, 0, 8), glm::vec3(8, 0, 0), 8, test::kSingleSided);
  test::add_grid(s, glm::vec3(-4, 0, -4), glm::vec3(8, 0, 0), glm::vec3(0, 4, 0), 8, test::kSingleSided);
  test::add_box(s, glm::vec3(-0.5f, 0.0f, -1.5f), glm::vec3(0.5f, 1.0f, -0.5f), test::kSingleSided);
  s.lights.push_back(test::point_light(glm::vec3(1.0f, 3.0f, 1.0f), 50.0f));
  s.lights.push_back(test::point_light(glm::vec3(-2.0f, 2.5f, 0.0f), 30.0f));
  if (moving_box) {
    const size_t first = s.meshes.size();
    test::add_box(s, glm::vec3(-2.0f, 0.3f, 0.5f), glm::vec3(-1.6f, 0.9f, 0.9f), test::kSingleSided);
    for (size_t m = first; m < s.meshes.size(); ++m) s.meshes[m].node = kMovingNode;
  }
  if (moving_light) {
    SceneLight carried = test::point_light(glm::vec3(-1.8f, 1.4f, 0.7f), 20.0f);
    carried.node = kMovingNode;
    s.lights.push_back(carried);
  }
  test::finalize(s);
  if (moving_box || moving_light) test::animate_translation(s, kMovingNode, glm::vec3(0.0f), glm::vec3(2, 0, 0), 2.0);
  return s;
}

inline Camera camera_at(double x, double y, double z, uint32_t w = 384, uint32_t h = 256) {
  return test::look_camera(glm::dvec3(x, y, z), glm::dvec3(0.0, 0.3, -1.5), w, h, 80.0);
}

}  // namespace dhr::server::reuse_test
