#include "scene/scene_motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dhr {

namespace {

bool same_light(const SceneLight& a, const SceneLight& b) {
  return a.position == b.position && a.direction == b.direction && a.tangent == b.tangent &&
         a.bitangent == b.bitangent;
}

}  // namespace

SceneMotion::SceneMotion(const Scene& scene) {
  scene_.animation = scene.animation;
  scene_.lights = scene.lights;
  scene_.meshes.reserve(scene.meshes.size());
  for (const SceneMesh& m : scene.meshes) {
    SceneMesh bare;
    bare.node = m.node;
    bare.T_world_local = m.T_world_local;
    scene_.meshes.push_back(std::move(bare));
  }
  if (scene.animation.empty()) return;
  for (std::uint32_t m = 0; m < scene.meshes.size(); ++m) {
    const SceneMesh& mesh = scene.meshes[m];
    if (scene.animation.find(mesh.node) == nullptr || mesh.positions.empty()) continue;
    MovingMesh moving;
    moving.mesh = m;
    moving.rest.min = glm::dvec3(std::numeric_limits<double>::max());
    moving.rest.max = glm::dvec3(std::numeric_limits<double>::lowest());
    for (const glm::vec3& p : mesh.positions) {
      moving.rest.min = glm::min(moving.rest.min, glm::dvec3(p));
      moving.rest.max = glm::max(moving.rest.max, glm::dvec3(p));
    }
    meshes_.push_back(moving);
  }
  std::stable_sort(meshes_.begin(), meshes_.end(), [&](const MovingMesh& a, const MovingMesh& b) {
    return scene.meshes[a.mesh].node < scene.meshes[b.mesh].node;
  });
  for (std::uint32_t i = 0; i < meshes_.size(); ++i) {
    const std::uint32_t node = scene.meshes[meshes_[i].mesh].node;
    if (nodes_.empty() || nodes_.back().node != node) nodes_.push_back(MovingNode{node, i, i});
    nodes_.back().end = i + 1;
  }
  for (std::size_t l = 0; l < std::min<std::size_t>(scene.lights.size(), 32); ++l) {
    const std::uint32_t node = scene.lights[l].node;
    if (node != kNoSceneNode && scene.animation.find(node) != nullptr) moving_lights_ |= 1u << l;
  }
}

void SceneMotion::moved_boxes(double t0, double t1, std::vector<WorldBox>& out,
                              const NodeOverrides* overrides) const {
  out.clear();
  for (const MovingNode& n : nodes_) {
    if (node_world_at(scene_, n.node, t0, overrides) == node_world_at(scene_, n.node, t1, overrides)) continue;
    WorldBox box{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
    for (std::uint32_t i = n.first; i < n.end; ++i) {
      const SceneMesh& mesh = scene_.meshes[meshes_[i].mesh];
      for (const double t : {t0, t1}) {
        const WorldBox at = moved_box(meshes_[i].rest, mesh_motion_at(scene_, mesh, t, overrides));
        box.min = glm::min(box.min, at.min);
        box.max = glm::max(box.max, at.max);
      }
    }
    out.push_back(box);
  }
  // Boxes that overlap become their union (a car's parts on their own nodes): fewer tests per pixel, and a point or
  // segment that met either meets the union.
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < out.size() && !merged; ++i) {
      for (std::size_t j = i + 1; j < out.size() && !merged; ++j) {
        if (!boxes_overlap(out[i], out[j])) continue;
        out[i].min = glm::min(out[i].min, out[j].min);
        out[i].max = glm::max(out[i].max, out[j].max);
        out.erase(out.begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
      }
    }
  }
}

std::uint32_t SceneMotion::moved_lights(double t0, double t1, const NodeOverrides* overrides) const {
  std::uint32_t moved = 0;
  for (std::uint32_t l = 0; l < 32; ++l) {
    if ((moving_lights_ >> l & 1u) == 0) continue;
    const SceneLight& light = scene_.lights[l];
    if (!same_light(light_at(scene_, light, t0, overrides), light_at(scene_, light, t1, overrides))) moved |= 1u << l;
  }
  return moved;
}

WorldBox moved_box(const WorldBox& box, const glm::dmat4& motion) {
  WorldBox out{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner((c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                            (c & 4) ? box.max.z : box.min.z);
    const glm::dvec3 p(motion * glm::dvec4(corner, 1.0));
    out.min = glm::min(out.min, p);
    out.max = glm::max(out.max, p);
  }
  return out;
}

WorldBox grown(const WorldBox& box, double margin) {
  return WorldBox{box.min - glm::dvec3(margin), box.max + glm::dvec3(margin)};
}

bool boxes_overlap(const WorldBox& a, const WorldBox& b) {
  return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
         a.min.z <= b.max.z && b.min.z <= a.max.z;
}

bool box_contains(const WorldBox& box, const glm::dvec3& p) {
  return p.x >= box.min.x && p.y >= box.min.y && p.z >= box.min.z && p.x <= box.max.x && p.y <= box.max.y &&
         p.z <= box.max.z;
}

namespace {

// The slab test of the segment a -> b against a box: the parameter interval [lo, hi] inside every slab the segment
// crosses, and for the axes it runs parallel to whether it lies outside their slab and how far from its faces.
struct Slabs {
  double lo = 0.0;
  double hi = 1.0;
  bool parallel_outside = false;
  double parallel_gap = std::numeric_limits<double>::infinity();
};

Slabs slabs(const glm::dvec3& a, const glm::dvec3& b, const WorldBox& box) {
  Slabs s;
  const glm::dvec3 d = b - a;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-300) {
      s.parallel_outside = s.parallel_outside || a[i] < box.min[i] || a[i] > box.max[i];
      s.parallel_gap = std::min({s.parallel_gap, std::abs(a[i] - box.min[i]), std::abs(box.max[i] - a[i])});
      continue;
    }
    double t0 = (box.min[i] - a[i]) / d[i];
    double t1 = (box.max[i] - a[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    s.lo = std::max(s.lo, t0);
    s.hi = std::min(s.hi, t1);
  }
  return s;
}

}  // namespace

bool segment_hits_box(const glm::dvec3& a, const glm::dvec3& b, const WorldBox& box) {
  const Slabs s = slabs(a, b, box);
  return !s.parallel_outside && s.lo <= s.hi;
}

double segment_box_gap(const glm::dvec3& a, const glm::dvec3& b, const WorldBox& box) {
  const Slabs s = slabs(a, b, box);
  return std::min(s.parallel_gap, std::abs(s.hi - s.lo) * glm::length(b - a));
}

}  // namespace dhr
