// App-moved nodes (DESIGN 5b, docs/motion.md "App-moved nodes"): the node transforms an application sent, each
// stamped with the scene time it takes effect, and the one rule both ends apply to them. A node's local transform at
// scene time t:
//   - before its first transform: its animation (or rest), as if no transform had been sent;
//   - from a transform's stamp until the next one's: that transform (its TRS replaces the animated or rest TRS);
//   - beyond the newest stamp: extrapolated from the newest two (translation and scale linearly, rotation along the
//     shortest arc), for at most kNodeExtrapolationHorizonNs past the newest stamp, then held there; with one
//     transform only, held.
// node_world_at, mesh_motion_at, light_at, scene_at and SceneMotion take a NodeOverrides (optional argument) and
// compose the overridden local transforms up the hierarchy like animated ones; the client and the server call the
// same functions on the same transforms and so agree bit for bit.
#pragma once
#include <cstddef>
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <limits>
#include <optional>
#include <vector>

#include "math/trs.hpp"
#include "scene/scene_animation.hpp"

namespace dhr {

// Extrapolation beyond the newest transform stops this far past its stamp (the node is then held there): a
// guess about where an application moves a node is trusted for a few frames of network delay, not for ever.
inline constexpr std::int64_t kNodeExtrapolationHorizonNs = 250'000'000;
// Transforms kept per node (the newest; older ones only decide scene times long gone).
inline constexpr std::size_t kNodeOverrideHistory = 8;

// What NodeOverrides::add did with a transform (everything but kAccepted is dropped).
enum class NodeTransformVerdict : std::uint8_t {
  kAccepted,
  kUnknownNode,  // not a node an application may move (SceneAnimation::nodes: animated, movable, or below one)
  kOutOfOrder,   // stamped at or before the newest transform accepted for that node
  kLate,         // stamped before `not_before_ns` (a scene time the receiver has already traced)
  kInvalid,      // not a usable TRS (non-finite, rotation not unit, scale not > 0) or a negative stamp
};
const char* to_string(NodeTransformVerdict verdict);

struct NodeTransformSample {
  std::int64_t scene_time_ns = 0;
  Trs trs;
};

// The transforms received for each movable node. Plain data: copy it to take a snapshot (a frame's trace).
class NodeOverrides {
 public:
  // Records `trs` for glTF node `node` from `scene_time_ns` on, unless the verdict says why not (checked in the
  // order of NodeTransformVerdict). Keeps the newest kNodeOverrideHistory transforms per node.
  NodeTransformVerdict add(const SceneAnimation& animation, std::uint32_t node, std::int64_t scene_time_ns,
                           const Trs& trs, std::int64_t not_before_ns = std::numeric_limits<std::int64_t>::min());

  bool empty() const { return nodes_.empty(); }
  // Increases with every accepted transform (a changed override set changes what is traced).
  std::uint64_t revision() const { return revision_; }
  // The node's overriding local TRS at scene time `t` (seconds), or std::nullopt where the rule gives the
  // animation or rest (no transform for the node, or t before its first stamp).
  std::optional<Trs> trs_at(std::uint32_t node, double t) const;
  // The same as a local transform (T * R * S).
  std::optional<glm::dmat4> local_at(std::uint32_t node, double t) const;
  // The newest transform accepted for `node`, or nullptr.
  const NodeTransformSample* newest(std::uint32_t node) const;

 private:
  struct Node {
    std::uint32_t node = 0;
    std::vector<NodeTransformSample> samples;  // increasing stamps, at most kNodeOverrideHistory
  };
  const Node* find(std::uint32_t node) const;
  std::vector<Node> nodes_;  // sorted by node
  std::uint64_t revision_ = 0;
};

// A stamp in seconds of scene time, as the sampling functions take it (the same conversion as the frame's).
inline double node_stamp_seconds(std::int64_t scene_time_ns) { return static_cast<double>(scene_time_ns) * 1e-9; }

// Whether `trs` is one a receiver accepts: finite, |rotation|^2 within 1e-3 of 1, every scale component > 0.
bool valid_trs(const Trs& trs);

// Local transform T * R * S of a TRS (the matrix glTF composes).
glm::dmat4 trs_matrix(const Trs& trs);

}  // namespace dhr
