// Sampling of glTF node animations (see scene/scene_animation.hpp): keys located by binary search, LINEAR (slerp
// for rotations), STEP and CUBICSPLINE (Hermite, tangents scaled by the key interval) in double, and world
// transforms composed up the stored hierarchy.
#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/matrix.hpp>

#include "scene/node_overrides.hpp"
#include "scene/scene.hpp"

namespace dhr {
namespace {

glm::dvec4 element(const AnimationTrack& track, std::size_t i) {
  const auto n = static_cast<std::size_t>(track.components());
  const float* v = track.values.data() + i * n;
  return glm::dvec4(v[0], v[1], v[2], n == 4 ? static_cast<double>(v[3]) : 0.0);
}

// glTF order (x, y, z, w) -> unit quaternion; identity when it has no length.
glm::dquat to_quat(const glm::dvec4& v) {
  const glm::dquat q(v.w, v.x, v.y, v.z);
  const double len = glm::length(q);
  if (!(len > 1e-12) || !std::isfinite(len)) return glm::dquat(1.0, 0.0, 0.0, 0.0);
  return q / len;
}

glm::dvec4 from_quat(const glm::dquat& q) { return glm::dvec4(q.x, q.y, q.z, q.w); }

// The track's value at local time `t` (x, y, z[, w]; rotations as a unit quaternion in glTF order).
glm::dvec4 sample(const AnimationTrack& track, double t) {
  const bool rotation = track.path == AnimationPath::kRotation;
  const bool cubic = track.interpolation == AnimationInterpolation::kCubicSpline;
  const std::size_t keys = track.times.size();
  // The value of key k (the middle element of a CUBICSPLINE triplet).
  const auto value = [&](std::size_t k) {
    const glm::dvec4 v = element(track, cubic ? 3 * k + 1 : k);
    return rotation ? from_quat(to_quat(v)) : v;
  };
  if (keys == 0) return rotation ? glm::dvec4(0.0, 0.0, 0.0, 1.0) : glm::dvec4(0.0);
  if (!(t > static_cast<double>(track.times.front()))) return value(0);
  if (t >= static_cast<double>(track.times.back())) return value(keys - 1);
  // times[k] <= t < times[k + 1]
  const auto next = std::upper_bound(track.times.begin(), track.times.end(), t,
                                     [](double x, float key) { return x < static_cast<double>(key); });
  const auto k = static_cast<std::size_t>(next - track.times.begin()) - 1;
  if (track.interpolation == AnimationInterpolation::kStep) return value(k);
  const double t0 = track.times[k];
  const double t1 = track.times[k + 1];
  const double dt = t1 - t0;
  const double u = (t - t0) / dt;
  if (!cubic) {
    if (rotation) return from_quat(slerp_shortest(to_quat(value(k)), to_quat(value(k + 1)), u));
    return value(k) * (1.0 - u) + value(k + 1) * u;
  }
  // glTF Appendix C: p(u) = (2u^3 - 3u^2 + 1) v_k + dt (u^3 - 2u^2 + u) b_k + (-2u^3 + 3u^2) v_k+1
  //                          + dt (u^3 - u^2) a_k+1, with b the out-tangent and a the in-tangent.
  const double u2 = u * u;
  const double u3 = u2 * u;
  const glm::dvec4 p = (2.0 * u3 - 3.0 * u2 + 1.0) * element(track, 3 * k + 1) +
                       dt * (u3 - 2.0 * u2 + u) * element(track, 3 * k + 2) +
                       (-2.0 * u3 + 3.0 * u2) * element(track, 3 * (k + 1) + 1) +
                       dt * (u3 - u2) * element(track, 3 * (k + 1));
  return rotation ? from_quat(to_quat(p)) : p;
}

// The node's local transform at scene time `t`: the application's where `overrides` has one, else rest TRS with
// its tracks applied (a later track on the same property wins), or the rest local transform for a node that is not
// animated itself.
glm::dmat4 local_at(const SceneAnimation& animation, const AnimatedNode& node, double t,
                    const NodeOverrides* overrides) {
  if (overrides) {
    if (const std::optional<glm::dmat4> app = overrides->local_at(node.node, t)) return *app;
  }
  if (node.track_count == 0) return node.rest_local;
  glm::dvec3 translation = node.translation;
  glm::dquat rotation = node.rotation;
  glm::dvec3 scale = node.scale;
  for (std::uint32_t i = 0; i < node.track_count; ++i) {
    const AnimationTrack& track = animation.tracks[node.first_track + i];
    const double duration = track.animation < animation.clips.size() ? animation.clips[track.animation].duration : 0.0;
    const glm::dvec4 v = sample(track, animation_local_time(t, duration));
    switch (track.path) {
      case AnimationPath::kTranslation:
        translation = glm::dvec3(v);
        break;
      case AnimationPath::kRotation:
        rotation = to_quat(v);
        break;
      case AnimationPath::kScale:
        scale = glm::dvec3(v);
        break;
    }
  }
  return trs_matrix(Trs{translation, rotation, scale});
}

glm::vec3 moved_direction(const glm::dmat4& motion, const glm::vec3& d) {
  const glm::dvec3 v = glm::dmat3(motion) * glm::dvec3(d);
  const double len = glm::length(v);
  if (!(len > 1e-12) || !std::isfinite(len)) return d;
  return glm::vec3(v / len);
}

}  // namespace

glm::dquat slerp_shortest(const glm::dquat& a, glm::dquat b, double u) {
  double d = glm::dot(a, b);
  if (d < 0.0) {
    b = -b;
    d = -d;
  }
  if (d > 0.9999995) return glm::normalize(a * (1.0 - u) + b * u);
  const double theta = std::acos(std::min(d, 1.0));
  const double s = std::sin(theta);
  return glm::normalize(a * (std::sin((1.0 - u) * theta) / s) + b * (std::sin(u * theta) / s));
}

const AnimatedNode* SceneAnimation::find(std::uint32_t node) const {
  const auto it = std::lower_bound(nodes.begin(), nodes.end(), node,
                                   [](const AnimatedNode& n, std::uint32_t index) { return n.node < index; });
  return it != nodes.end() && it->node == node ? &*it : nullptr;
}

double animation_local_time(double t, double duration) {
  if (!std::isfinite(t) || t < 0.0) t = 0.0;
  if (!(duration > 0.0) || !std::isfinite(duration)) return 0.0;
  return std::fmod(t, duration);
}

glm::dmat4 node_world_at(const Scene& scene, std::uint32_t node, double t, const NodeOverrides* overrides) {
  const SceneAnimation& animation = scene.animation;
  const AnimatedNode* n = animation.find(node);
  if (!n) {
    for (const SceneMesh& mesh : scene.meshes) {
      if (mesh.node == node) return mesh.T_world_local;
    }
    return glm::dmat4(1.0);
  }
  // Walk up while the parent moves too (iteratively: hierarchies may be deep), then compose downwards.
  std::vector<const AnimatedNode*> chain;
  for (const AnimatedNode* p = n; p; p = p->parent == kNoSceneNode ? nullptr : animation.find(p->parent)) {
    chain.push_back(p);
    if (chain.size() > animation.nodes.size()) break;  // a malformed (cyclic) hierarchy: stop
  }
  glm::dmat4 world = chain.back()->parent_rest_world;
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) world = world * local_at(animation, **it, t, overrides);
  return world;
}

glm::dmat4 mesh_motion_at(const Scene& scene, const SceneMesh& mesh, double t, const NodeOverrides* overrides) {
  if (!scene.animation.find(mesh.node)) return glm::dmat4(1.0);
  return node_world_at(scene, mesh.node, t, overrides) * glm::inverse(mesh.T_world_local);
}

SceneLight light_at(const Scene& scene, const SceneLight& light, double t, const NodeOverrides* overrides) {
  if (light.node == kNoSceneNode) return light;
  const AnimatedNode* n = scene.animation.find(light.node);
  if (!n) return light;
  const glm::dmat4 motion = node_world_at(scene, light.node, t, overrides) * glm::inverse(n->rest_world);
  SceneLight moved = light;
  moved.position = glm::vec3(motion * glm::dvec4(glm::dvec3(light.position), 1.0));
  moved.direction = moved_direction(motion, light.direction);
  moved.tangent = moved_direction(motion, light.tangent);
  moved.bitangent = moved_direction(motion, light.bitangent);
  return moved;
}

}  // namespace dhr
