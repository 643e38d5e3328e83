#include "render/client_motion.hpp"

#include <algorithm>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <limits>
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

ClientMotion::ClientMotion(const Scene& scene, std::span<const ClientMesh> meshes) : scene_motion_(scene) {
  for (uint32_t i = 0; i < meshes.size(); ++i) {
    const uint32_t source = meshes[i].source;
    if (source >= scene.meshes.size()) throw std::invalid_argument("ClientMotion: a mesh without its scene mesh");
    const SceneMesh& m = scene.meshes[source];
    source_.push_back(source);
    const bool moves = scene.animation.find(m.node) != nullptr;
    mesh_moves_.push_back(moves ? 1 : 0);
    if (moves) moving_meshes_.push_back(i);
    WorldBox local{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
    const glm::dmat4 local_from_world = glm::inverse(m.T_world_local);
    for (const glm::vec3& p : m.positions) {
      const glm::dvec3 q(local_from_world * glm::dvec4(glm::dvec3(p), 1.0));
      local.min = glm::min(local.min, q);
      local.max = glm::max(local.max, q);
    }
    rest_local_bounds_.push_back(local);
  }
  for (uint32_t l = 0; l < scene.lights.size(); ++l) {
    const uint32_t node = scene.lights[l].node;
    const bool moves = node != kNoSceneNode && scene.animation.find(node) != nullptr;
    light_moves_.push_back(moves ? 1 : 0);
    if (moves) moving_lights_.push_back(l);
  }
}

glm::dmat4 ClientMotion::node_world(uint32_t mesh, double t, const NodeOverrides* overrides) const {
  const SceneMesh& m = scene_motion_.scene().meshes[source_[mesh]];
  return mesh_moves(mesh) ? node_world_at(scene_motion_.scene(), m.node, t, overrides) : m.T_world_local;
}

glm::dmat4 ClientMotion::motion_at(uint32_t mesh, double t, const NodeOverrides* overrides) const {
  const Scene& scene = scene_motion_.scene();
  return mesh_moves(mesh) ? mesh_motion_at(scene, scene.meshes[source_[mesh]], t, overrides) : glm::dmat4(1.0);
}

WorldBox ClientMotion::world_bounds_at(uint32_t mesh, double t, const NodeOverrides* overrides) const {
  return moved_box(rest_local_bounds_[mesh], node_world(mesh, t, overrides));
}

void ClientMotion::sample(double t, std::span<const ClientMesh> meshes, MovedScene& out,
                          const NodeOverrides* overrides) const {
  const size_t n = meshes.size();
  if (!out.sampled || out.motion.size() != n || out.lights.size() != scene_motion_.scene().lights.size()) {
    out.motion.assign(n, glm::dmat4(1.0));
    out.centre.resize(n);
    out.radius.resize(n);
    for (size_t i = 0; i < n; ++i) {
      out.centre[i] = meshes[i].origin;
      out.radius[i] = meshes[i].radius;
    }
    out.lights = scene_motion_.scene().lights;
  }
  out.time_s = t;
  out.sampled = true;
  out.overrides = overrides;
  for (uint32_t i : moving_meshes_) {
    const glm::dmat4 m = motion_at(i, t, overrides);
    out.motion[i] = m;
    out.centre[i] = glm::dvec3(m * glm::dvec4(meshes[i].origin, 1.0));
    out.radius[i] = meshes[i].radius * max_scale(m);
  }
  for (uint32_t l : moving_lights_)
    out.lights[l] = light_at(scene_motion_.scene(), scene_motion_.scene().lights[l], t, overrides);
}

}  // namespace dhr::render
