#include "render/scene_motion.hpp"

#include <algorithm>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <stdexcept>

#include "render/client_scene.hpp"

namespace dhr::render {
namespace {

// Largest stretch of the motion's 3x3 (its largest column length bounds it for the sphere test; exact for a
// rigid motion with uniform scale).
double max_scale(const glm::dmat4& m) {
  return std::max({glm::length(glm::dvec3(m[0])), glm::length(glm::dvec3(m[1])), glm::length(glm::dvec3(m[2]))});
}

}  // namespace

void Aabb::extend(const glm::dvec3& p) {
  min = glm::min(min, p);
  max = glm::max(max, p);
}

SceneMotion::SceneMotion(const Scene& scene, std::span<const ClientMesh> meshes) {
  scene_.animation = scene.animation;
  scene_.lights = scene.lights;
  scene_.meshes.reserve(scene.meshes.size());
  for (const SceneMesh& m : scene.meshes) {
    SceneMesh bare;
    bare.node = m.node;
    bare.T_world_local = m.T_world_local;
    scene_.meshes.push_back(std::move(bare));
  }
  for (uint32_t i = 0; i < meshes.size(); ++i) {
    const uint32_t source = meshes[i].source;
    if (source >= scene.meshes.size()) throw std::invalid_argument("SceneMotion: a mesh without its scene mesh");
    const SceneMesh& m = scene.meshes[source];
    source_.push_back(source);
    const bool moves = scene.animation.find(m.node) != nullptr;
    mesh_moves_.push_back(moves ? 1 : 0);
    if (moves) moving_meshes_.push_back(i);
    Aabb local;
    const glm::dmat4 local_from_world = glm::inverse(m.T_world_local);
    for (const glm::vec3& p : m.positions) local.extend(glm::dvec3(local_from_world * glm::dvec4(glm::dvec3(p), 1.0)));
    rest_local_bounds_.push_back(local);
  }
  for (uint32_t l = 0; l < scene.lights.size(); ++l) {
    const uint32_t node = scene.lights[l].node;
    const bool moves = node != kNoSceneNode && scene.animation.find(node) != nullptr;
    light_moves_.push_back(moves ? 1 : 0);
    if (moves) moving_lights_.push_back(l);
  }
}

glm::dmat4 SceneMotion::node_world(uint32_t mesh, double t) const {
  const SceneMesh& m = scene_.meshes[source_[mesh]];
  return mesh_moves(mesh) ? node_world_at(scene_, m.node, t) : m.T_world_local;
}

glm::dmat4 SceneMotion::motion_at(uint32_t mesh, double t) const {
  return mesh_moves(mesh) ? mesh_motion_at(scene_, scene_.meshes[source_[mesh]], t) : glm::dmat4(1.0);
}

Aabb SceneMotion::world_bounds_at(uint32_t mesh, double t) const {
  const Aabb& local = rest_local_bounds_[mesh];
  Aabb out;
  if (local.empty()) return out;
  const glm::dmat4 world = node_world(mesh, t);
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner((k & 1) ? local.max.x : local.min.x, (k & 2) ? local.max.y : local.min.y,
                            (k & 4) ? local.max.z : local.min.z);
    out.extend(glm::dvec3(world * glm::dvec4(corner, 1.0)));
  }
  return out;
}

void SceneMotion::sample(double t, std::span<const ClientMesh> meshes, MovedScene& out) const {
  const size_t n = meshes.size();
  if (!out.sampled || out.motion.size() != n || out.lights.size() != scene_.lights.size()) {
    out.motion.assign(n, glm::dmat4(1.0));
    out.centre.resize(n);
    out.radius.resize(n);
    for (size_t i = 0; i < n; ++i) {
      out.centre[i] = meshes[i].origin;
      out.radius[i] = meshes[i].radius;
    }
    out.lights = scene_.lights;
  }
  out.time_s = t;
  out.sampled = true;
  for (uint32_t i : moving_meshes_) {
    const glm::dmat4 m = motion_at(i, t);
    out.motion[i] = m;
    out.centre[i] = glm::dvec3(m * glm::dvec4(meshes[i].origin, 1.0));
    out.radius[i] = meshes[i].radius * max_scale(m);
  }
  for (uint32_t l : moving_lights_) out.lights[l] = light_at(scene_, scene_.lights[l], t);
}

}  // namespace dhr::render
