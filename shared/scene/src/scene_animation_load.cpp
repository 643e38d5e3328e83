// glTF animations -> SceneAnimation: checks every channel's sampler data (accessor types, counts, key times, finite
// values) and the key limit, ignores with a warning what is not played (weights channels, nodes outside the loaded
// scene), and records the rest hierarchy of every node that can move. The JSON structure (indices, paths,
// interpolations) was checked by GltfValidator::check_animations.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "scene_internal.hpp"

namespace dhr::scene_detail {
namespace {

bool is_normalized_int(const tinygltf::Accessor& a) {
  return a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
                          a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                          a.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
                          a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
}

class AnimationLoader {
 public:
  AnimationLoader(const tinygltf::Model& model, const std::vector<NodeRest>& nodes, WarningSink& warnings,
                  SceneAnimation* out)
      : model_(model), nodes_(nodes), warnings_(warnings), out_(out) {}

  bool run(const std::vector<std::uint32_t>& walk_order, const SceneLoadOptions& options, std::string* out_error) {
    if (!check_key_limit(options, out_error)) return false;
    for (std::size_t a = 0; a < model_.animations.size(); ++a) {
      if (!load_animation(a, out_error)) return false;
    }
    collect_nodes(walk_order);
    return true;
  }

 private:
  bool fail(const std::string& message, std::string* out_error) {
    *out_error = message;
    return false;
  }

  bool check_key_limit(const SceneLoadOptions& options, std::string* out_error) {
    std::uint64_t keys = 0;
    for (const tinygltf::Animation& anim : model_.animations) {
      for (const tinygltf::AnimationSampler& s : anim.samplers) {
        if (s.input >= 0 && static_cast<std::size_t>(s.input) < model_.accessors.size()) {
          keys += model_.accessors[static_cast<std::size_t>(s.input)].count;
        }
      }
    }
    if (keys > options.max_animation_keys) {
      return fail(format("the animations have %llu keys, more than the limit of %llu (max_animation_keys)",
                         static_cast<unsigned long long>(keys),
                         static_cast<unsigned long long>(options.max_animation_keys)),
                  out_error);
    }
    return true;
  }

  // A sampler's key times, read and checked once (cached by sampler index).
  bool read_times(const tinygltf::Animation& anim, int sampler, const std::string& label,
                  const std::vector<float>** out_times, std::string* out_error) {
    auto it = times_.find(sampler);
    if (it == times_.end()) {
      const int input = anim.samplers[static_cast<std::size_t>(sampler)].input;
      const std::string where = label + format(": sampler %d input (accessor %d)", sampler, input);
      if (input < 0 || static_cast<std::size_t>(input) >= model_.accessors.size()) {
        return fail(where + " does not exist", out_error);
      }
      const tinygltf::Accessor& a = model_.accessors[static_cast<std::size_t>(input)];
      if (a.type != TINYGLTF_TYPE_SCALAR || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || a.normalized) {
        return fail(where + ": key times must be a SCALAR float accessor", out_error);
      }
      std::vector<float> times;
      std::string error;
      if (!read_accessor_floats(model_, input, 1, &times, &error)) return fail(where + ": " + error, out_error);
      if (times.empty()) return fail(where + ": has no keys", out_error);
      for (std::size_t k = 0; k < times.size(); ++k) {
        if (!std::isfinite(times[k])) return fail(where + format(": key time %zu is not finite", k), out_error);
        if (times[k] < 0.0f) {
          return fail(where + format(": key time %zu is negative (%g s)", k, static_cast<double>(times[k])),
                      out_error);
        }
        if (k > 0 && !(times[k] > times[k - 1])) {
          return fail(where + format(": key times are not strictly increasing (key %zu: %g s after %g s)", k,
                                     static_cast<double>(times[k]), static_cast<double>(times[k - 1])),
                      out_error);
        }
      }
      it = times_.emplace(sampler, std::move(times)).first;
    }
    *out_times = &it->second;
    return true;
  }

  // Reads the output of channel's sampler into `track` (times already set), checking type, count and values.
  bool read_values(const tinygltf::AnimationSampler& s, int sampler, const std::string& label, AnimationTrack* track,
                   std::string* out_error) {
    const std::string where = label + format(": sampler %d output (accessor %d)", sampler, s.output);
    if (s.output < 0 || static_cast<std::size_t>(s.output) >= model_.accessors.size()) {
      return fail(where + " does not exist", out_error);
    }
    const tinygltf::Accessor& a = model_.accessors[static_cast<std::size_t>(s.output)];
    const bool rotation = track->path == AnimationPath::kRotation;
    const bool is_float = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT && !a.normalized;
    if (rotation && (a.type != TINYGLTF_TYPE_VEC4 || !(is_float || is_normalized_int(a)))) {
      return fail(where + ": rotations must be a VEC4 accessor of floats or normalized integers", out_error);
    }
    if (!rotation && (a.type != TINYGLTF_TYPE_VEC3 || !is_float)) {
      return fail(where + ": translations and scales must be a VEC3 float accessor", out_error);
    }
    // The count is checked before reading, so the key limit also bounds what is allocated here.
    const std::size_t per_key = track->interpolation == AnimationInterpolation::kCubicSpline ? 3 : 1;
    if (a.count != per_key * track->times.size()) {
      return fail(where + format(": has %zu values for %zu keys (count must be %zu)", a.count, track->times.size(),
                                 per_key * track->times.size()),
                  out_error);
    }
    std::string error;
    if (!read_accessor_floats(model_, s.output, track->components(), &track->values, &error)) {
      return fail(where + ": " + error, out_error);
    }
    for (std::size_t i = 0; i < track->values.size(); ++i) {
      if (!std::isfinite(track->values[i])) {
        return fail(where + format(": value %zu is NaN or infinite", i / static_cast<std::size_t>(track->components())),
                    out_error);
      }
    }
    return true;
  }

  bool load_animation(std::size_t a, std::string* out_error) {
    const tinygltf::Animation& anim = model_.animations[a];
    const auto clip_index = static_cast<std::uint32_t>(out_->clips.size());
    AnimationClip clip;
    clip.name = anim.name.empty() ? format("animation%zu", a) : anim.name;
    const std::string base = format("animation %zu ('%s')", a, clip.name.c_str());
    times_.clear();
    for (std::size_t c = 0; c < anim.channels.size(); ++c) {
      const tinygltf::AnimationChannel& ch = anim.channels[c];
      const std::string label = base + format(" channel %zu", c);
      if (ch.sampler < 0 || static_cast<std::size_t>(ch.sampler) >= anim.samplers.size()) {
        return fail(label + format(": sampler %d does not exist", ch.sampler), out_error);
      }
      if (ch.target_node < 0 || static_cast<std::size_t>(ch.target_node) >= model_.nodes.size()) {
        return fail(label + format(": target node %d does not exist", ch.target_node), out_error);
      }
      AnimationTrack track;
      if (ch.target_path == "translation") {
        track.path = AnimationPath::kTranslation;
      } else if (ch.target_path == "rotation") {
        track.path = AnimationPath::kRotation;
      } else if (ch.target_path == "scale") {
        track.path = AnimationPath::kScale;
      } else if (ch.target_path != "weights") {
        return fail(label + ": unknown path \"" + ch.target_path + "\"", out_error);
      }
      const tinygltf::AnimationSampler& s = anim.samplers[static_cast<std::size_t>(ch.sampler)];
      if (s.interpolation == "STEP") {
        track.interpolation = AnimationInterpolation::kStep;
      } else if (s.interpolation == "CUBICSPLINE") {
        track.interpolation = AnimationInterpolation::kCubicSpline;
      } else if (!s.interpolation.empty() && s.interpolation != "LINEAR") {
        return fail(label + format(": sampler %d has unknown interpolation \"%s\"", ch.sampler,
                                   s.interpolation.c_str()),
                    out_error);
      }
      const std::vector<float>* times = nullptr;
      if (!read_times(anim, ch.sampler, label, &times, out_error)) return false;
      clip.duration = std::max(clip.duration, static_cast<double>(times->back()));
      const auto node = static_cast<std::uint32_t>(ch.target_node);
      if (ch.target_path == "weights") {
        warnings_.add(label + format(": morph target weights (node %u) are not supported; channel ignored", node));
        continue;
      }
      if (node >= nodes_.size() || !nodes_[node].in_scene) {
        warnings_.add(label + format(": node %u is not in the loaded scene; channel ignored", node));
        continue;
      }
      if (model_.nodes[node].matrix.size() == 16) {
        return fail(label + format(": node %u is given by a matrix, which glTF forbids for animated nodes", node),
                    out_error);
      }
      track.animation = clip_index;
      track.node = node;
      track.times = *times;
      if (!read_values(s, ch.sampler, label, &track, out_error)) return false;
      out_->tracks.push_back(std::move(track));
    }
    out_->clips.push_back(std::move(clip));
    return true;
  }

  // A node the application may move at run time (`extras: {"dhr_movable": true}`); any other value is named and
  // ignored.
  bool movable(std::uint32_t n) {
    const tinygltf::Value& extras = model_.nodes[n].extras;
    if (!extras.IsObject() || !extras.Has("dhr_movable")) return false;
    const tinygltf::Value& v = extras.Get("dhr_movable");
    if (!v.IsBool()) {
      warnings_.add(format("node %u: extras.dhr_movable is not true or false; ignored (the node is not movable)", n));
      return false;
    }
    if (v.Get<bool>() && !nodes_[n].in_scene) {
      warnings_.add(format("node %u: extras.dhr_movable on a node outside the loaded scene; ignored", n));
      return false;
    }
    return v.Get<bool>();
  }

  // Every node of the scene that is animated, movable or below such a node, sorted by index, with its tracks.
  void collect_nodes(const std::vector<std::uint32_t>& walk_order) {
    std::stable_sort(out_->tracks.begin(), out_->tracks.end(),
                     [](const AnimationTrack& x, const AnimationTrack& y) { return x.node < y.node; });
    std::vector<std::uint8_t> moving(nodes_.size(), 0);
    for (const AnimationTrack& t : out_->tracks) moving[t.node] = 1;
    for (std::uint32_t n = 0; n < nodes_.size() && n < model_.nodes.size(); ++n)
      if (movable(n)) moving[n] = 1;
    for (std::uint32_t n : walk_order) {  // parents come first
      const std::uint32_t p = nodes_[n].parent;
      if (p != kNoSceneNode && moving[p]) moving[n] = 1;
    }
    std::size_t track = 0;
    for (std::uint32_t n = 0; n < nodes_.size(); ++n) {
      if (!moving[n]) continue;
      AnimatedNode node;
      node.node = n;
      node.name = model_.nodes[n].name;
      node.parent = nodes_[n].parent;
      if (node.parent != kNoSceneNode) node.parent_rest_world = nodes_[node.parent].world;
      const tinygltf::Node& src = model_.nodes[n];
      if (src.translation.size() == 3) {
        node.translation = glm::dvec3(src.translation[0], src.translation[1], src.translation[2]);
      }
      if (src.rotation.size() == 4) {
        const glm::dquat q(src.rotation[3], src.rotation[0], src.rotation[1], src.rotation[2]);
        const double len = glm::length(q);
        if (len > 1e-12 && std::isfinite(len)) node.rotation = q / len;  // as the walk does
      }
      if (src.scale.size() == 3) node.scale = glm::dvec3(src.scale[0], src.scale[1], src.scale[2]);
      node.rest_local = nodes_[n].local;
      node.rest_world = nodes_[n].world;
      node.first_track = static_cast<std::uint32_t>(track);
      while (track < out_->tracks.size() && out_->tracks[track].node == n) ++track;
      node.track_count = static_cast<std::uint32_t>(track) - node.first_track;
      out_->nodes.push_back(node);
      out_->moving_nodes.push_back(n);
    }
  }

  const tinygltf::Model& model_;
  const std::vector<NodeRest>& nodes_;
  WarningSink& warnings_;
  SceneAnimation* out_;
  std::map<int, std::vector<float>> times_;  // by sampler index, for the animation being read
};

}  // namespace

bool load_animations(const tinygltf::Model& model, const std::vector<NodeRest>& nodes,
                     const std::vector<std::uint32_t>& walk_order, const SceneLoadOptions& options,
                     WarningSink& warnings, SceneAnimation* out, std::string* out_error) {
  return AnimationLoader(model, nodes, warnings, out).run(walk_order, options, out_error);
}

}  // namespace dhr::scene_detail
