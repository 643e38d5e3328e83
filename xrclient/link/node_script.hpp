// App-moved nodes from a script (dhr-xrclient --node-script FILE; docs/motion.md, "App-moved nodes"): JSON lines
//   {"t": 1.5, "node": "ToyCar", "translation": [x, y, z], "rotation": [x, y, z, w], "scale": [x, y, z]}
// each one the node's local TRS from scene time t (seconds) on. "node" is a glTF node name or index of a node the
// scene lets move (animated, `extras.dhr_movable`, or below one); a missing translation, rotation or scale keeps
// the node's rest value. Blank lines and lines starting with '#' are skipped. NodeScriptPlayer sends each line
// through VisibilityClient::send_node_transform when the frames' scene clock reaches it, and records what it sent
// (as the server decodes it) in the NodeOverrides the client's own rendering uses.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "link/visibility_client.hpp"
#include "scene/node_overrides.hpp"
#include "scene/scene.hpp"

namespace dhr::client {

struct NodeScriptStep {
  int64_t scene_time_ns = 0;
  uint32_t node = 0;
  Trs trs;
  size_t line = 0;  // 1-based, for messages
};

// The steps of `text`, in file order; std::nullopt and "line N: why" in *out_error for the first bad line (not
// JSON, an unknown or unmovable node, a value missing, not finite or out of range, a time not after the same
// node's previous one).
std::optional<std::vector<NodeScriptStep>> parse_node_script(std::string_view text, const Scene& scene,
                                                             std::string* out_error);
// The same for a file; "FILE:N: why" (or "FILE: cannot read") in *out_error.
std::optional<std::vector<NodeScriptStep>> load_node_script(const std::string& path, const Scene& scene,
                                                            std::string* out_error);

class NodeScriptPlayer {
 public:
  // `scene` must outlive the player.
  NodeScriptPlayer(std::vector<NodeScriptStep> steps, const Scene& scene);

  // Sends, in file order, every step due at `scene_time_ns` (its t <= the scene time) not sent yet; a step the
  // client could not send (no session yet) waits for the next call. Returns how many were sent.
  size_t play(int64_t scene_time_ns, VisibilityClient& client);

  // What was sent, as the server decodes it: the client's copy of the session's app-moved nodes.
  const NodeOverrides& overrides() const { return overrides_; }
  size_t sent() const { return next_; }
  size_t size() const { return steps_.size(); }

 private:
  std::vector<NodeScriptStep> steps_;
  const Scene* scene_;
  size_t next_ = 0;
  NodeOverrides overrides_;
};

}  // namespace dhr::client
