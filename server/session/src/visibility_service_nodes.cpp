// VisibilityService: app-moved nodes (docs/motion.md, "App-moved nodes"). A NodeTransform joins its session's
// NodeOverrides, which every later frame of the session is traced with; one that cannot take effect is dropped,
// counted per reason and logged (at most one line a second, naming the node and why).
#include "session/service_session.hpp"

#include "log/log.hpp"

#include <limits>

namespace dhr::server {

void VisibilityService::handle_node_transform(Session& s, const NodeTransform& transform, int64_t now_ns) {
  ++stats_.node_transforms_received;
  // Late: before the scene time of a pose already traced (that frame went out without it, and the rule cannot move
  // a node in frames already sent). The pose's own scene time, not the predicted one the frame was traced at: a
  // transform stamped within the prediction horizon is news about a time the server only guessed.
  const int64_t not_before = s.have_traced ? s.traced_scene_time_ns : std::numeric_limits<int64_t>::min();
  static const SceneAnimation kNothingMoves;
  const SceneAnimation* animation = tracer_.scene_animation();
  const NodeTransformVerdict verdict = s.overrides.add(animation ? *animation : kNothingMoves, transform.node,
                                                       transform.scene_time_ns, transform.trs, not_before);
  uint64_t* counter = nullptr;
  switch (verdict) {
    case NodeTransformVerdict::kAccepted: ++stats_.node_transforms_applied; return;
    case NodeTransformVerdict::kUnknownNode: counter = &stats_.node_transforms_dropped_unknown_node; break;
    case NodeTransformVerdict::kOutOfOrder: counter = &stats_.node_transforms_dropped_out_of_order; break;
    case NodeTransformVerdict::kLate: counter = &stats_.node_transforms_dropped_late; break;
    case NodeTransformVerdict::kInvalid:  // the decoder refuses these: counted as rejected should one get here
      counter = &stats_.datagrams_rejected;
      break;
  }
  ++*counter;
  if (last_node_drop_log_ns_ == 0 || now_ns - last_node_drop_log_ns_ >= net::kNsPerSecond) {
    last_node_drop_log_ns_ = now_ns == 0 ? 1 : now_ns;
    log::warn("session %016llx: dropped the transform of node %u stamped %.6f s: %s (%llu so far)",
              static_cast<unsigned long long>(s.token), transform.node, node_stamp_seconds(transform.scene_time_ns),
              to_string(verdict), static_cast<unsigned long long>(*counter));
  }
}

}  // namespace dhr::server
