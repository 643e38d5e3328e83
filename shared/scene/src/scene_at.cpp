// scene_at: the exhaustive reference of an animated scene at a scene time (see scene/scene_at.hpp).
#include "scene/scene_at.hpp"

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace dhr {

glm::vec3 moved_position(const glm::dmat4& motion, const glm::vec3& p) {
  return glm::vec3(glm::dvec3(motion * glm::dvec4(glm::dvec3(p), 1.0)));
}

glm::dmat3 normal_matrix(const glm::dmat4& motion) { return glm::transpose(glm::inverse(glm::dmat3(motion))); }

glm::vec3 moved_normal(const glm::dmat3& normal_matrix, const glm::vec3& n) {
  const glm::dvec3 v = normal_matrix * glm::dvec3(n);
  const double len = glm::length(v);
  if (!(len > 1e-12) || !std::isfinite(len)) return n;
  return glm::vec3(v / len);
}

Scene scene_at(const Scene& scene, double t, const NodeOverrides* overrides) {
  Scene out = scene;
  if (scene.animation.empty()) return out;
  for (SceneMesh& mesh : out.meshes) {
    if (!scene.animation.find(mesh.node)) continue;
    const glm::dmat4 motion = mesh_motion_at(scene, mesh, t, overrides);
    const glm::dmat3 nm = normal_matrix(motion);
    for (glm::vec3& p : mesh.positions) p = moved_position(motion, p);
    for (glm::vec3& n : mesh.normals) n = moved_normal(nm, n);
    mesh.T_world_local = node_world_at(scene, mesh.node, t, overrides);
  }
  for (SceneLight& light : out.lights) light = light_at(scene, light, t, overrides);
  out.animation = SceneAnimation{};  // a snapshot: its meshes and lights are already where they are at t
  out.bounds = SceneBounds{};
  for (const SceneMesh& mesh : out.meshes) {
    for (std::uint32_t i : mesh.indices) {
      if (i < mesh.positions.size()) out.bounds.extend(mesh.positions[i]);  // as the loader: triangle vertices
    }
  }
  return out;
}

}  // namespace dhr
