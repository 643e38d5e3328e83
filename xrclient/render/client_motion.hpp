// What moves in a ClientScene (glTF node animations, DESIGN 5b) and where it is at a scene time, per ClientMesh (the
// client's draw list; scene/scene_motion.hpp's dhr::SceneMotion answers what moved between two times). ClientMotion is
// fixed at load: per client mesh whether it moves and its rest bounds in its node's local frame, per light whether
// it moves, and the animation to sample. MovedScene is one frame's sample (scene time): every moving mesh's
// motion (rest world -> world, mesh_motion_at) and bounding sphere, and the lights (light_at). The raster passes
// draw a moving mesh with its motion (scene_draw.hpp, mesh_push.hpp); static meshes are drawn as before, so a
// scene without animation renders the same bits with or without a MovedScene.
#pragma once
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "scene/scene.hpp"
#include "scene/scene_motion.hpp"

namespace dhr::render {

struct ClientMesh;

// One frame's sample of the scene (ClientMotion::sample). Sized once; sampling again does not allocate.
struct MovedScene {
  double time_s = 0.0;
  bool sampled = false;                // false: never sampled (everything at rest)
  std::vector<glm::dmat4> motion;      // per ClientMesh: rest world -> world at time_s (identity: static)
  std::vector<glm::dvec3> centre;      // per ClientMesh: bounding-sphere centre at time_s (world)
  std::vector<double> radius;          // per ClientMesh: bounding-sphere radius at time_s
  std::vector<SceneLight> lights;      // the scene's lights at time_s
  const NodeOverrides* overrides = nullptr;  // the app-moved nodes sampled with (the warp's motion rule uses them)
};

class ClientMotion {
 public:
  ClientMotion() = default;
  // `meshes`: the ClientScene's meshes (ClientMesh::source names their Scene mesh).
  ClientMotion(const Scene& scene, std::span<const ClientMesh> meshes);

  bool animated() const { return !moving_meshes_.empty() || !moving_lights_.empty(); }
  // What moved between two scene times (the warp's motion rule, warp_motion.hpp).
  const SceneMotion& scene_motion() const { return scene_motion_; }
  bool mesh_moves(uint32_t mesh) const { return mesh_moves_[mesh] != 0; }
  bool light_moves(uint32_t light) const { return light_moves_[light] != 0; }
  const std::vector<uint32_t>& moving_meshes() const { return moving_meshes_; }  // ClientMesh indices
  const std::vector<uint32_t>& moving_lights() const { return moving_lights_; }  // light indices
  // The mesh's rest positions' bounds in its node's local frame (inverse(SceneMesh::T_world_local) * rest world).
  const WorldBox& rest_local_bounds(uint32_t mesh) const { return rest_local_bounds_[mesh]; }
  // World transform of the mesh's node at scene time t (rest: SceneMesh::T_world_local); with `overrides`, app-moved
  // nodes where scene/node_overrides.hpp puts them.
  glm::dmat4 node_world(uint32_t mesh, double t, const NodeOverrides* overrides = nullptr) const;
  // Rest world -> world at t (mesh_motion_at); identity for a static mesh.
  glm::dmat4 motion_at(uint32_t mesh, double t, const NodeOverrides* overrides = nullptr) const;
  // World bounds at t: the rest local box's corners through node_world (conservative for any affine motion).
  WorldBox world_bounds_at(uint32_t mesh, double t, const NodeOverrides* overrides = nullptr) const;

  // Samples every mesh and light at scene time t into `out` (static ones at rest); `meshes` as constructed. With
  // `overrides` (kept in out.overrides: it must outlive the frame), app-moved nodes are where the app put them.
  void sample(double t, std::span<const ClientMesh> meshes, MovedScene& out,
              const NodeOverrides* overrides = nullptr) const;

 private:
  SceneMotion scene_motion_;  // what moved between two times; its scene(): the animation, lights, nodes (no vertices)
  std::vector<uint32_t> source_;  // per ClientMesh: index into scene_.meshes
  std::vector<uint8_t> mesh_moves_;
  std::vector<uint8_t> light_moves_;
  std::vector<uint32_t> moving_meshes_;
  std::vector<uint32_t> moving_lights_;
  std::vector<WorldBox> rest_local_bounds_;
};

// Scene time of a FramePose (nanoseconds) in the seconds the animation functions take.
inline double scene_seconds(int64_t scene_time_ns) { return static_cast<double>(scene_time_ns) * 1e-9; }

}  // namespace dhr::render
