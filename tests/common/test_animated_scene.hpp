// A small animated Scene built in code (no glTF): a static triangle (node 0), a triangle on a moving node (node 1,
// rest at (0, 0, 2); it moves 4 m along +x and turns 90 degrees about +y over a 2 s loop), a point light on the
// moving node and a fixed one. For tests of scene_at, SceneMotion and what follows motion.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/scene.hpp"

namespace dhr::test {

inline constexpr std::uint32_t kStaticNode = 0;
inline constexpr std::uint32_t kMovingNode = 1;

// One triangle on `node` at rest world position `offset` (+z normals).
inline SceneMesh triangle(std::uint32_t node, const glm::vec3& offset) {
  SceneMesh m;
  m.name = "tri" + std::to_string(node);
  m.node = node;
  m.T_world_local = glm::translate(glm::dmat4(1.0), glm::dvec3(offset));
  m.positions = {offset, offset + glm::vec3(1, 0, 0), offset + glm::vec3(0, 1, 0)};
  m.normals.assign(3, glm::vec3(0, 0, 1));
  m.indices = {0, 1, 2};
  return m;
}

// A static triangle (node 0), a moving triangle (node 1, rest at (0, 0, 2)) and a point light on node 1.
inline Scene animated_scene() {
  Scene s;
  s.materials.emplace_back();
  s.meshes.push_back(triangle(kStaticNode, glm::vec3(0.0f)));
  s.meshes.push_back(triangle(kMovingNode, glm::vec3(0.0f, 0.0f, 2.0f)));
  SceneLight light;
  light.name = "moving";
  light.position = glm::vec3(0.0f, 1.0f, 2.0f);
  light.node = kMovingNode;
  s.lights.push_back(light);
  SceneLight fixed = light;
  fixed.name = "fixed";
  fixed.node = kNoSceneNode;
  s.lights.push_back(fixed);
  for (const SceneMesh& m : s.meshes) {
    for (const glm::vec3& p : m.positions) s.bounds.extend(p);
  }

  AnimatedNode node;
  node.node = kMovingNode;
  node.translation = glm::dvec3(0.0, 0.0, 2.0);
  node.rest_local = glm::translate(glm::dmat4(1.0), node.translation);
  node.rest_world = node.rest_local;
  node.first_track = 0;
  node.track_count = 2;
  s.animation.nodes.push_back(node);
  s.animation.moving_nodes.push_back(kMovingNode);
  s.animation.clips.push_back(AnimationClip{"move", 2.0});
  AnimationTrack move;
  move.node = kMovingNode;
  move.path = AnimationPath::kTranslation;
  move.times = {0.0f, 2.0f};
  move.values = {0, 0, 2, 4, 0, 2};  // x: 0 -> 4 m over 2 s
  s.animation.tracks.push_back(move);
  AnimationTrack turn;
  turn.node = kMovingNode;
  turn.path = AnimationPath::kRotation;
  turn.times = {0.0f, 2.0f};
  const float h = std::sqrt(0.5f);
  turn.values = {0, 0, 0, 1, 0, h, 0, h};  // 0 -> 90 degrees about +y
  s.animation.tracks.push_back(turn);
  return s;
}

// Gives `node` (at rest at the identity) one looping clip of `seconds`: a linear translation from `from` to `to`.
inline void animate_translation(Scene& s, std::uint32_t node, const glm::vec3& from, const glm::vec3& to,
                                double seconds) {
  AnimatedNode n;
  n.node = node;
  n.first_track = static_cast<std::uint32_t>(s.animation.tracks.size());
  n.track_count = 1;
  s.animation.nodes.push_back(n);
  s.animation.moving_nodes.push_back(node);
  s.animation.clips.push_back(AnimationClip{"translate", seconds});
  AnimationTrack track;
  track.node = node;
  track.path = AnimationPath::kTranslation;
  track.times = {0.0f, static_cast<float>(seconds)};
  track.values = {from.x, from.y, from.z, to.x, to.y, to.z};
  s.animation.tracks.push_back(track);
}

}  // namespace dhr::test
