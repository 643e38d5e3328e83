// glTF 2.0 node animations (translation, rotation, scale; LINEAR, STEP, CUBICSPLINE) as plain data, and their
// sampling on one scene clock. Every animation loops with its own duration (the last key time of its samplers;
// duration 0: constant). The scene itself stays flattened at rest (Scene::meshes, Scene::lights); these functions
// give where an animated node, mesh or light is at a scene time. Pure functions in double; tinygltf stays in the
// .cpp files. Include scene/scene.hpp (it includes this header) for Scene, SceneMesh and SceneLight.
#pragma once
#include <cstdint>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace dhr {

// "No glTF node": a light made from a spec, or a root's parent.
inline constexpr std::uint32_t kNoSceneNode = 0xffffffffu;

enum class AnimationPath : std::uint8_t { kTranslation, kRotation, kScale };
enum class AnimationInterpolation : std::uint8_t { kLinear, kStep, kCubicSpline };

// One glTF animation channel (a node property driven by a sampler).
struct AnimationTrack {
  std::uint32_t animation = 0;  // index into SceneAnimation::clips
  std::uint32_t node = 0;       // glTF node index (always in SceneAnimation::nodes)
  AnimationPath path = AnimationPath::kTranslation;
  AnimationInterpolation interpolation = AnimationInterpolation::kLinear;
  std::vector<float> times;  // seconds: at least one, finite, >= 0, strictly increasing
  // components() floats per element: x, y, z (translation, scale) or x, y, z, w (rotation quaternion, glTF order).
  // One element per key; CUBICSPLINE: three per key (in-tangent, value, out-tangent), as glTF stores them.
  std::vector<float> values;

  int components() const { return path == AnimationPath::kRotation ? 4 : 3; }
};

// One glTF animation.
struct AnimationClip {
  std::string name;       // the glTF name, else "animation<N>"
  double duration = 0.0;  // seconds: the largest last input time of its samplers; 0: constant
};

// A node whose world transform can change: animated itself, marked movable by the application (glTF node
// `extras: {"dhr_movable": true}`), or below such a node.
struct AnimatedNode {
  std::uint32_t node = 0;               // glTF node index
  std::string name;                     // the glTF node's name ("" when it has none): scripts name nodes by it
  std::uint32_t parent = kNoSceneNode;  // glTF index of its parent; kNoSceneNode for a scene root
  glm::dmat4 parent_rest_world{1.0};    // the parent's world transform at rest (identity for a root)
  glm::dvec3 translation{0.0};          // rest local TRS (a node given by `matrix` is never animated itself)
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  glm::dvec3 scale{1.0};
  glm::dmat4 rest_local{1.0};  // the rest local transform as the loader composed it (matrix or T * R * S)
  glm::dmat4 rest_world{1.0};  // the world transform at rest (equals SceneMesh::T_world_local of its meshes)
  std::uint32_t first_track = 0;  // its tracks: SceneAnimation::tracks[first_track, first_track + track_count)
  std::uint32_t track_count = 0;  // 0: not animated itself (moves with an animated ancestor)
};

struct SceneAnimation {
  std::vector<AnimationClip> clips;
  std::vector<AnimatedNode> nodes;     // sorted by glTF node index
  std::vector<AnimationTrack> tracks;  // grouped by node (in `nodes` order), file order within a node
  std::vector<std::uint32_t> moving_nodes;  // sorted glTF node indices of `nodes`

  // Nothing moves: no animation track and no node an application may move (extras.dhr_movable).
  bool empty() const { return tracks.empty() && nodes.empty(); }
  // The entry of glTF node `node`, or nullptr when it does not move.
  const AnimatedNode* find(std::uint32_t node) const;
};

struct Scene;
struct SceneMesh;
struct SceneLight;
class NodeOverrides;  // scene/node_overrides.hpp: transforms an application sent (app-moved nodes)

// Time within an animation of `duration` at scene time `t`: t mod duration; 0 for a duration of 0. A negative or
// non-finite scene time counts as 0.
double animation_local_time(double t, double duration);

// Shortest-path spherical interpolation of unit quaternions (nlerp where they are nearly equal); u outside [0, 1]
// continues along the same arc (extrapolation).
glm::dquat slerp_shortest(const glm::dquat& a, glm::dquat b, double u);

// World transform of glTF node `node` at scene time `t` (seconds). A node that does not move gets its rest world
// transform: that of its first mesh instance (SceneMesh::T_world_local), else identity (a node with neither meshes
// nor animation is not stored). With `overrides`, a moving node's local transform is the app's where
// NodeOverrides::local_at gives one (the node and everything below it follow).
glm::dmat4 node_world_at(const Scene& scene, std::uint32_t node, double t, const NodeOverrides* overrides = nullptr);

// Maps a mesh's rest world positions to their positions at `t`: node_world_at(mesh.node, t) *
// inverse(mesh.T_world_local). Identity for a mesh whose node does not move.
glm::dmat4 mesh_motion_at(const Scene& scene, const SceneMesh& mesh, double t,
                          const NodeOverrides* overrides = nullptr);

// The light at `t`: position, direction, tangent and bitangent moved with its node (directions renormalized);
// unchanged for a light without a node or on a node that does not move. Extents are not rescaled.
SceneLight light_at(const Scene& scene, const SceneLight& light, double t, const NodeOverrides* overrides = nullptr);

}  // namespace dhr
