// The moving test scene of the client's motion tests (client_motion_test, client_motion_warp_test): a static floor,
// a small occluder on an animated node (translated and turned), three point lights (one near, one out of range, one
// moving), the camera that sees the occluder's shadow, and a CPU shadow-ray test against a scene.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "client_test_helpers.hpp"
#include "scene/scene.hpp"

namespace dhr::render {

inline constexpr uint32_t kFloorNode = 0;
inline constexpr uint32_t kOccluderNode = 1;
inline constexpr uint32_t kLightNode = 2;
inline constexpr uint32_t kFarNode = 3;

// A node animated along `from` -> `to` over 2 s (and, with `turn`, turned 0 -> 60 degrees about +z).
inline void animate(Scene& s, uint32_t node, const glm::dvec3& from, const glm::dvec3& to, bool turn) {
  AnimatedNode n;
  n.node = node;
  n.translation = from;
  n.rest_local = glm::translate(glm::dmat4(1.0), from);
  n.rest_world = n.rest_local;
  n.first_track = static_cast<uint32_t>(s.animation.tracks.size());
  n.track_count = turn ? 2 : 1;
  s.animation.nodes.push_back(n);
  s.animation.moving_nodes.push_back(node);
  AnimationTrack move;
  move.node = node;
  move.path = AnimationPath::kTranslation;
  move.times = {0.0f, 2.0f};
  move.values = {float(from.x), float(from.y), float(from.z), float(to.x), float(to.y), float(to.z)};
  s.animation.tracks.push_back(move);
  if (turn) {
    AnimationTrack t;
    t.node = node;
    t.path = AnimationPath::kRotation;
    t.times = {0.0f, 2.0f};
    t.values = {0, 0, 0, 1, 0, 0, 0.5f, 0.8660254f};
    s.animation.tracks.push_back(t);
  }
}

// Floor (y = 0, static), a 0.4 m occluder at (0, 1, 0) on an animated node (to x = 2 over 2 s, turning), point
// lights: A above it (infinite range), B far away with a 5 m range, C far away on a moving node. With `far_mover`,
// another animated quad far behind the camera (never on screen) instead of animating the occluder.
inline Scene moving_scene(bool far_mover = false) {
  Scene s;
  s.materials.push_back(test::colour_material(glm::vec4(0.8f, 0.7f, 0.6f, 1.0f), true));
  SceneMesh floor = test::quad_mesh({-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, {-4, 0, -4}, 0);
  floor.node = kFloorNode;
  s.meshes.push_back(floor);
  SceneMesh occ = test::quad_mesh({-0.2, 1, 0.2}, {0.2, 1, 0.2}, {0.2, 1, -0.2}, {-0.2, 1, -0.2}, 0);
  occ.node = kOccluderNode;
  occ.T_world_local = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 1, 0));
  s.meshes.push_back(occ);
  if (far_mover) {
    SceneMesh far = test::quad_mesh({-0.2, 1, 40.2}, {0.2, 1, 40.2}, {0.2, 1, 39.8}, {-0.2, 1, 39.8}, 0);
    far.node = kFarNode;
    far.T_world_local = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 1, 40));
    s.meshes.push_back(far);
    animate(s, kFarNode, {0, 1, 40}, {2, 1, 40}, true);
  } else {
    animate(s, kOccluderNode, {0, 1, 0}, {2, 1, 0}, true);
  }
  SceneLight a;
  a.name = "A";
  a.position = glm::vec3(0, 3, 0);
  a.intensity = 10.0f;
  s.lights.push_back(a);
  SceneLight b = a;
  b.name = "B";
  b.position = glm::vec3(30, 3, 0);
  b.range = 5.0f;
  s.lights.push_back(b);
  SceneLight c = b;
  c.name = "C";
  c.position = glm::vec3(-30, 3, 0);
  c.node = kLightNode;
  s.lights.push_back(c);
  animate(s, kLightNode, {-30, 3, 0}, {-29, 3, 0}, false);
  // glTF node order: keep the animation's nodes sorted by index.
  std::sort(s.animation.nodes.begin(), s.animation.nodes.end(),
            [](const AnimatedNode& x, const AnimatedNode& y) { return x.node < y.node; });
  std::sort(s.animation.moving_nodes.begin(), s.animation.moving_nodes.end());
  std::stable_sort(s.animation.tracks.begin(), s.animation.tracks.end(),
                   [](const AnimationTrack& x, const AnimationTrack& y) { return x.node < y.node; });
  uint32_t first = 0;
  for (AnimatedNode& n : s.animation.nodes) {
    n.first_track = first;
    first += n.track_count;
  }
  s.animation.clips.push_back(AnimationClip{"move", 2.0});
  test::finish_scene(s);
  return s;
}

inline View camera_view() {
  View v;
  v.pose = test::look_at({0.8, 2.2, 1.6}, {1.0, 0.9, 0.0});
  v.fov = test::fov_from_tangents(0.8, 0.6);
  return v;
}

// Whether the segment p -> light crosses a triangle of `scene` (Moller-Trumbore, double).
inline bool occluded(const Scene& scene, const glm::dvec3& p, const glm::dvec3& light) {
  const glm::dvec3 d = light - p;
  for (const SceneMesh& m : scene.meshes) {
    for (size_t i = 0; i + 2 < m.indices.size(); i += 3) {
      const glm::dvec3 a(m.positions[m.indices[i]]), b(m.positions[m.indices[i + 1]]), c(m.positions[m.indices[i + 2]]);
      const glm::dvec3 e1 = b - a, e2 = c - a, h = glm::cross(d, e2);
      const double det = glm::dot(e1, h);
      if (std::abs(det) < 1e-12) continue;
      const glm::dvec3 s = p - a;
      const double u = glm::dot(s, h) / det;
      const glm::dvec3 q = glm::cross(s, e1);
      const double v = glm::dot(d, q) / det;
      const double t = glm::dot(e2, q) / det;
      if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 1e-6 && t < 1.0 - 1e-6) return true;
    }
  }
  return false;
}

}  // namespace dhr::render
