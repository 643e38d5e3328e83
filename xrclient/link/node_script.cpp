// dhr-xrclient --node-script: parsing the JSON lines and playing them on the scene clock (link/node_script.hpp).
#include "link/node_script.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace dhr::client {
namespace {

using nlohmann::json;

// Scene times up to this (seconds) fit an int64 of nanoseconds with room to spare (about 292 years).
constexpr double kMaxScriptSeconds = 1.0e9;

// The glTF index of the movable node `value` names (a name or an index); std::nullopt with *why otherwise.
std::optional<uint32_t> resolve_node(const json& value, const SceneAnimation& animation, std::string* why) {
  if (value.is_number_unsigned()) {
    const uint64_t index = value.get<uint64_t>();
    if (index <= UINT32_MAX && animation.find(static_cast<uint32_t>(index))) return static_cast<uint32_t>(index);
    *why = "node " + value.dump() + " is not a node the scene lets move (animated, extras.dhr_movable, or below one)";
    return std::nullopt;
  }
  if (value.is_string()) {
    const std::string name = value.get<std::string>();
    for (const AnimatedNode& n : animation.nodes)
      if (!name.empty() && n.name == name) return n.node;
    *why = "no node named \"" + name + "\" that the scene lets move (animated, extras.dhr_movable, or below one)";
    return std::nullopt;
  }
  *why = "\"node\" must be a glTF node name or index";
  return std::nullopt;
}

// `count` finite numbers from key `key` of `line` into `out`, or false with *why.
bool read_numbers(const json& line, const char* key, size_t count, double* out, std::string* why) {
  const auto it = line.find(key);
  if (it == line.end()) return true;  // the rest value stays
  if (!it->is_array() || it->size() != count) {
    *why = std::string("\"") + key + "\" must be an array of " + std::to_string(count) + " numbers";
    return false;
  }
  for (size_t i = 0; i < count; ++i) {
    if (!(*it)[i].is_number() || !std::isfinite((*it)[i].get<double>())) {
      *why = std::string("\"") + key + "\" must hold finite numbers";
      return false;
    }
    out[i] = (*it)[i].get<double>();
  }
  return true;
}

// One line into `out`, or false with *why.
bool parse_step(const json& line, const SceneAnimation& animation, NodeScriptStep& out, std::string* why) {
  if (!line.is_object()) {
    *why = "expected a JSON object";
    return false;
  }
  for (const auto& [key, value] : line.items()) {
    if (key != "t" && key != "node" && key != "translation" && key != "rotation" && key != "scale") {
      *why = "unknown key \"" + key + "\" (t, node, translation, rotation, scale)";
      return false;
    }
  }
  const auto t = line.find("t");
  if (t == line.end() || !t->is_number() || !(t->get<double>() >= 0.0) || !(t->get<double>() <= kMaxScriptSeconds)) {
    *why = "\"t\" must be a scene time in seconds, 0 to 1e9";
    return false;
  }
  out.scene_time_ns = std::llround(t->get<double>() * 1e9);
  const auto node = line.find("node");
  if (node == line.end()) {
    *why = "\"node\" is missing";
    return false;
  }
  const std::optional<uint32_t> index = resolve_node(*node, animation, why);
  if (!index) return false;
  out.node = *index;
  const AnimatedNode& rest = *animation.find(*index);
  double translation[3] = {rest.translation.x, rest.translation.y, rest.translation.z};
  double rotation[4] = {rest.rotation.x, rest.rotation.y, rest.rotation.z, rest.rotation.w};  // glTF order
  double scale[3] = {rest.scale.x, rest.scale.y, rest.scale.z};
  if (!read_numbers(line, "translation", 3, translation, why) || !read_numbers(line, "rotation", 4, rotation, why) ||
      !read_numbers(line, "scale", 3, scale, why))
    return false;
  out.trs = Trs{glm::dvec3(translation[0], translation[1], translation[2]),
                glm::dquat(rotation[3], rotation[0], rotation[1], rotation[2]), glm::dvec3(scale[0], scale[1], scale[2])};
  if (!valid_trs(out.trs)) {
    *why = "not a usable transform: the rotation must be a unit quaternion [x, y, z, w] and every scale > 0";
    return false;
  }
  out.trs.rotation = glm::normalize(out.trs.rotation);
  return true;
}

}  // namespace

std::optional<std::vector<NodeScriptStep>> parse_node_script(std::string_view text, const Scene& scene,
                                                             std::string* out_error) {
  std::vector<NodeScriptStep> steps;
  std::map<uint32_t, int64_t> newest;  // per node, the newest time so far
  std::istringstream in{std::string(text)};
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::string why;
    NodeScriptStep step;
    step.line = number;
    const json value = json::parse(line, nullptr, false);
    if (value.is_discarded()) {
      why = "not a JSON object";
    } else if (parse_step(value, scene.animation, step, &why)) {
      if (!steps.empty() && step.scene_time_ns < steps.back().scene_time_ns) {
        why = "\"t\" is before the previous line's: lines must be in time order";
      } else if (const auto it = newest.find(step.node); it != newest.end() && step.scene_time_ns <= it->second) {
        why = "\"t\" must be after the same node's previous line (node " + std::to_string(step.node) + ")";
      }
    }
    if (!why.empty()) {
      *out_error = "line " + std::to_string(number) + ": " + why;
      return std::nullopt;
    }
    newest[step.node] = step.scene_time_ns;
    steps.push_back(step);
  }
  return steps;
}

std::optional<std::vector<NodeScriptStep>> load_node_script(const std::string& path, const Scene& scene,
                                                            std::string* out_error) {
  std::ifstream file(path);
  if (!file) {
    *out_error = path + ": cannot read the file";
    return std::nullopt;
  }
  std::ostringstream text;
  text << file.rdbuf();
  std::string error;
  std::optional<std::vector<NodeScriptStep>> steps = parse_node_script(text.str(), scene, &error);
  if (!steps) *out_error = path + ":" + error.substr(5);  // "line N: why" -> "FILE:N: why"
  return steps;
}

NodeScriptPlayer::NodeScriptPlayer(std::vector<NodeScriptStep> steps, const Scene& scene)
    : steps_(std::move(steps)), scene_(&scene) {}

size_t NodeScriptPlayer::play(int64_t scene_time_ns, VisibilityClient& client) {
  size_t sent = 0;
  while (next_ < steps_.size() && steps_[next_].scene_time_ns <= scene_time_ns) {
    const NodeScriptStep& step = steps_[next_];
    const std::optional<NodeTransform> decoded = client.send_node_transform(step.node, step.scene_time_ns, step.trs);
    if (!decoded) break;  // no session yet: try again with the next frame
    // The script's own checks make every step acceptable here (movable node, increasing per node).
    overrides_.add(scene_->animation, decoded->node, decoded->scene_time_ns, decoded->trs);
    ++next_;
    ++sent;
  }
  return sent;
}

}  // namespace dhr::client
