// glTF JSON validation (see scene_validate.cpp): nodes, the node hierarchy, scenes and animations.
#include <algorithm>
#include <string>
#include <vector>

#include "scene_validator.hpp"

namespace dhr::scene_detail {

bool GltfValidator::check_nodes() {
  static const std::pair<const char*, std::size_t> kVectors[] = {
      {"matrix", 16}, {"translation", 3}, {"rotation", 4}, {"scale", 3}};
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Json& n = *nodes_[i];
    const std::string path = at("nodes", i);
    if (!index_member(n, "mesh", path, meshes_.size(), "mesh", false) ||
        !index_member(n, "camera", path, cameras_.size(), "camera", false) ||
        !index_member(n, "skin", path, skins_.size(), "skin", false)) {
      return false;
    }
    for (const auto& [k, count] : kVectors) {
      if (!numbers_member(n, k, path, count)) return false;
    }
    if (n.contains("matrix") && (n.contains("translation") || n.contains("rotation") || n.contains("scale"))) {
      warnings_.add(path + ": has both a matrix and TRS properties; using the matrix");
    }
    if (const Json* children = member(n, "children", path, Json::value_t::array)) {
      for (std::size_t c = 0; c < children->size(); ++c) {
        std::uint64_t child = 0;
        if (!as_uint((*children)[c], &child) || child >= nodes_.size()) {
          return fail(at(key(path, "children"), c), "is not a valid node index (" + (*children)[c].dump() + ")");
        }
      }
    }
    if (auto ext = n.find("extensions"); ext != n.end()) {
      if (auto lp = ext->find("KHR_lights_punctual"); lp != ext->end()) {
        if (!index_member(*lp, "light", path + ".extensions.KHR_lights_punctual", light_count_, "light", true)) {
          return false;
        }
      }
    }
    if (!error_.empty()) return false;
  }
  return true;
}

// The hierarchy must be a forest: each node has at most one parent and following parents never loops.
bool GltfValidator::check_hierarchy() {
  constexpr std::size_t kNone = ~std::size_t{0};
  std::vector<std::size_t> parent(nodes_.size(), kNone);
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    auto children = nodes_[i]->find("children");
    if (children == nodes_[i]->end()) continue;
    for (const Json& c : *children) {
      const std::size_t child = c.get<std::size_t>();
      if (child == i) return fail(at("nodes", i), "node cycle: node " + std::to_string(i) + " is its own child");
      if (parent[child] != kNone && parent[child] != i) {
        // A node with two parents may still be a cycle (0 -> 1 -> 0 gives node 0 parents 1 and none).
        return fail(at("nodes", child), "is a child of both node " + std::to_string(parent[child]) + " and node " +
                                            std::to_string(i) + " (the node hierarchy must be a tree)");
      }
      parent[child] = i;
    }
  }
  // 0 = unknown, 1 = on the current upward walk, 2 = reaches a root.
  std::vector<std::uint8_t> state(nodes_.size(), 0);
  std::vector<std::size_t> walk;
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    walk.clear();
    std::size_t n = i;
    while (n != kNone && state[n] == 0) {
      state[n] = 1;
      walk.push_back(n);
      n = parent[n];
    }
    if (n != kNone && state[n] == 1) {
      // walk runs child -> parent; print the loop parent -> child, starting and ending at one node.
      const auto start = std::find(walk.begin(), walk.end(), n);
      std::string cycle = "node cycle: ";
      for (auto it = walk.end(); it != start;) {
        --it;
        cycle += std::to_string(*it) + " -> ";
      }
      cycle += std::to_string(walk.back());
      return fail("nodes", cycle);
    }
    for (std::size_t w : walk) state[w] = 2;
  }
  return true;
}

bool GltfValidator::check_scenes() {
  for (std::size_t i = 0; i < scenes_.size(); ++i) {
    const std::string path = at("scenes", i);
    if (const Json* roots = member(*scenes_[i], "nodes", path, Json::value_t::array)) {
      for (std::size_t r = 0; r < roots->size(); ++r) {
        std::uint64_t node = 0;
        if (!as_uint((*roots)[r], &node) || node >= nodes_.size()) {
          return fail(at(key(path, "nodes"), r), "is not a valid node index (" + (*roots)[r].dump() + ")");
        }
      }
    }
    if (!error_.empty()) return false;
  }
  if (scenes_.empty()) return fail("scenes", "the file has no scenes, so there is nothing to show");
  std::int64_t scene = 0;
  if (!index_member(root_, "scene", "", scenes_.size(), "scene", false, &scene)) return false;
  const Json& chosen = *scenes_[static_cast<std::size_t>(scene)];
  if (!chosen.contains("nodes") || chosen["nodes"].empty()) {
    return fail(at("scenes", static_cast<std::size_t>(scene)), "the scene to show has no nodes");
  }
  return true;
}

// Animations: every channel needs a sampler, a target node and a known path; every sampler an input and an output
// accessor and a known interpolation. Paths name the animation ("animations[0] ('walk').channels[1].target").
bool GltfValidator::check_animations() {
  for (std::size_t a = 0; a < animations_.size(); ++a) {
    const Json& anim = *animations_[a];
    std::string base = at("animations", a);
    if (auto name = anim.find("name"); name != anim.end() && name->is_string()) {
      base += " ('" + name->get<std::string>() + "')";
    }
    std::vector<const Json*> samplers, channels;
    if (!array_of_objects(anim, "samplers", base, &samplers) || !array_of_objects(anim, "channels", base, &channels)) {
      return false;
    }
    for (std::size_t s = 0; s < samplers.size(); ++s) {
      const std::string path = at(key(base, "samplers"), s);
      if (!index_member(*samplers[s], "input", path, accessors_.size(), "accessor", true) ||
          !index_member(*samplers[s], "output", path, accessors_.size(), "accessor", true)) {
        return false;
      }
      if (const Json* interp = member(*samplers[s], "interpolation", path, Json::value_t::string)) {
        const std::string v = interp->get<std::string>();
        if (v != "LINEAR" && v != "STEP" && v != "CUBICSPLINE") {
          return fail(key(path, "interpolation"), "unknown interpolation \"" + v + "\" (LINEAR, STEP, CUBICSPLINE)");
        }
      }
      if (!error_.empty()) return false;
    }
    for (std::size_t c = 0; c < channels.size(); ++c) {
      const std::string path = at(key(base, "channels"), c);
      if (!index_member(*channels[c], "sampler", path, samplers.size(), "sampler", true)) return false;
      const Json* target = member(*channels[c], "target", path, Json::value_t::object, true);
      if (!target) return false;
      const std::string tpath = key(path, "target");
      if (!target->contains("node")) {
        return fail(tpath, "has no node (channels without a target node are not supported)");
      }
      if (!index_member(*target, "node", tpath, nodes_.size(), "node", true)) return false;
      const Json* p = member(*target, "path", tpath, Json::value_t::string, true);
      if (!p) return false;
      const std::string v = p->get<std::string>();
      if (v != "translation" && v != "rotation" && v != "scale" && v != "weights") {
        return fail(key(tpath, "path"), "unknown path \"" + v + "\" (translation, rotation, scale, weights)");
      }
    }
  }
  return true;
}

}  // namespace dhr::scene_detail
