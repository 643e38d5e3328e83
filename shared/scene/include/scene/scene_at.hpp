// The scene as it is at a scene time: the simple, exhaustive reference for animated scenes. Every mesh on a moving
// node gets its vertices moved (mesh_motion_at) and every light on a moving node is replaced by light_at; static
// meshes and lights are copied as they are. Used as the truth by tests (and later by dhr-eval); the server's
// acceleration structure updates only what moves instead (docs/server.md, "Motion").
#pragma once
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.hpp"

namespace dhr {

// A copy of `scene` at scene time `t` (seconds): moving meshes' positions transformed by mesh_motion_at, their
// normals by its inverse-transpose (renormalized), their T_world_local set to node_world_at; lights replaced by
// light_at; bounds recomputed from the (moved) triangle vertices, as the loader computes them. A static scene (animation.empty()) gives an identical copy.
// The result is a static scene (animation cleared): a snapshot, traced like any static scene. With `overrides`, the
// app-moved nodes are where scene/node_overrides.hpp's rule puts them at t.
Scene scene_at(const Scene& scene, double t, const NodeOverrides* overrides = nullptr);

// The vertex math scene_at applies, shared with the server so that both move a vertex to the same float:
// a rest world position moved by `motion` (in double, rounded once).
glm::vec3 moved_position(const glm::dmat4& motion, const glm::vec3& p);
// The normal matrix of `motion`: the inverse-transpose of its upper 3x3.
glm::dmat3 normal_matrix(const glm::dmat4& motion);
// A unit normal moved by a normal matrix and renormalized; unchanged when the result has no length.
glm::vec3 moved_normal(const glm::dmat3& normal_matrix, const glm::vec3& n);

}  // namespace dhr
