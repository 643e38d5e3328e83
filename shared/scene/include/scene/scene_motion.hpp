// What moved between two scene times, as the client's warp needs it (DESIGN 5b: visibility traced at one scene time
// is trusted at another only where nothing that could change it moved). Visibility at t1 can differ from that at t0
// only through geometry present at t0 or at t1 (where it was, where it is; the path between does not matter): a
// moving node whose pose differs between them contributes one world box holding its meshes at both times, and a
// light whose placement differs moved. One box per node, not two per mesh: the warp tests every pixel against each
// box, and a frame's motion is small beside the box. The boxes bound the rest vertices moved by mesh_motion_at, so they hold every
// moved vertex. Pure CPU, double; the warp's shader and its CPU reference test points and shadow segments against
// them (segment_hits_box).
#pragma once
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "scene/scene.hpp"

namespace dhr {

struct WorldBox {
  glm::dvec3 min{0.0};
  glm::dvec3 max{0.0};
};

class SceneMotion {
 public:
  SceneMotion() = default;
  // Indexes the scene's moving meshes (their rest boxes) and lights, and keeps what sampling needs: the animation,
  // the lights and each mesh's node and T_world_local (no vertices).
  explicit SceneMotion(const Scene& scene);

  // The scene without vertices: node_world_at, mesh_motion_at and light_at work on it as on the full scene.
  const Scene& scene() const { return scene_; }

  // The scene has a mesh or a light on a moving node.
  bool moves() const { return !meshes_.empty() || moving_lights_ != 0; }
  std::size_t moving_meshes() const { return meshes_.size(); }
  // Bit l (l < 32): light l is on a moving node.
  std::uint32_t moving_lights() const { return moving_lights_; }

  // One box per moving node whose pose differs between t0 and t1: around its meshes at t0 and at t1; boxes that
  // overlap are merged into their union. Clears `out` first; keeps its storage. With `overrides`, app-moved nodes
  // are where scene/node_overrides.hpp puts them at each time.
  void moved_boxes(double t0, double t1, std::vector<WorldBox>& out, const NodeOverrides* overrides = nullptr) const;
  // Bit l: light l (of the first 32) is placed differently at t0 and t1 (position, direction or orientation).
  std::uint32_t moved_lights(double t0, double t1, const NodeOverrides* overrides = nullptr) const;

 private:
  struct MovingMesh {
    std::uint32_t mesh = 0;
    WorldBox rest;  // of its rest world positions
  };
  // meshes_ is sorted by node: a node's meshes are meshes_[first, end).
  struct MovingNode {
    std::uint32_t node = 0;
    std::uint32_t first = 0;
    std::uint32_t end = 0;
  };
  std::vector<MovingNode> nodes_;
  Scene scene_;
  std::vector<MovingMesh> meshes_;
  std::uint32_t moving_lights_ = 0;
};

// The world box of `box`'s eight corners moved by `motion`.
WorldBox moved_box(const WorldBox& box, const glm::dmat4& motion);
// `box` grown by `margin` on every side.
WorldBox grown(const WorldBox& box, double margin);
bool box_contains(const WorldBox& box, const glm::dvec3& p);
// The boxes share a point (faces touching count).
bool boxes_overlap(const WorldBox& a, const WorldBox& b);
// The segment from a to b meets the box (slab test; a segment inside counts).
bool segment_hits_box(const glm::dvec3& a, const glm::dvec3& b, const WorldBox& box);
// How far the slab test of segment_hits_box is from flipping, in metres along the segment: the gap between the
// entry and exit parameters (or the distance outside a slab the segment runs parallel to). Small: a rounding of the
// segment or the box may change the answer.
double segment_box_gap(const glm::dvec3& a, const glm::dvec3& b, const WorldBox& box);

}  // namespace dhr
