#include "session/service_stats_json.hpp"

namespace dhr::server {

nlohmann::ordered_json to_json(const ServiceStats& s) {
  nlohmann::ordered_json decode = nlohmann::ordered_json::object();
  for (size_t i = 1; i < kDecodeErrorCount; ++i)
    if (s.decode_errors.counts[i] != 0) decode[to_string(static_cast<DecodeError>(i))] = s.decode_errors.counts[i];
  return {{"datagrams_received", s.datagrams_received},
          {"datagrams_rejected", s.datagrams_rejected},
          {"decode_errors", decode},
          {"wrong_version", s.wrong_version},
          {"unknown_token", s.unknown_token},
          {"wrong_peer", s.wrong_peer},
          {"unexpected_type", s.unexpected_type},
          {"auth_failed", s.auth_failed},
          {"replayed", s.replayed},
          {"unauthenticated", s.unauthenticated},
          {"hellos_replayed", s.hellos_replayed},
          {"rate_decreases", s.rate_decreases},
          {"sessions_rate_capped", s.sessions_rate_capped},
          {"datagrams_shed", s.datagrams_shed},
          {"hellos", s.hellos},
          {"hellos_repeated", s.hellos_repeated},
          {"hellos_rejected", s.hellos_rejected},
          {"sessions_opened", s.sessions_opened},
          {"sessions_closed", s.sessions_closed},
          {"sessions_timed_out", s.sessions_timed_out},
          {"sessions_closed_by_peer", s.sessions_closed_by_peer},
          {"sessions_replaced", s.sessions_replaced},
          {"sessions_active", s.sessions_active},
          {"poses_received", s.poses_received},
          {"poses_stale", s.poses_stale},
          {"poses_superseded", s.poses_superseded},
          {"poses_skipped_identical", s.poses_skipped_identical},
          {"frames_traced", s.frames_traced},
          {"trace_errors", s.trace_errors},
          {"shards_sent", s.shards_sent},
          {"datagrams_sent", s.datagrams_sent},
          {"bytes_sent", s.bytes_sent},
          {"send_failures", s.send_failures},
          {"heartbeats_received", s.heartbeats_received},
          {"heartbeats_sent", s.heartbeats_sent},
          {"byes_sent", s.byes_sent},
          {"replies_suppressed", s.replies_suppressed},
          {"frames_predicted", s.frames_predicted},
          {"prediction_fallbacks", s.prediction_fallbacks},
          {"prediction_horizon_ms", s.prediction_horizon_ms},
          {"eyes_fov_widened", s.eyes_fov_widened},
          {"fov_span_ratio", s.fov_span_ratio},
          {"sessions_soft", s.sessions_soft},
          {"soft_pairs", s.soft_pairs},
          {"soft_contributing_pairs", s.soft_contributing_pairs},
          {"soft_refined_pairs", s.soft_refined_pairs},
          {"soft_shadow_rays", s.soft_shadow_rays},
          {"reused_pixels", s.reused_pixels},
          {"reused_pairs", s.reused_pairs},
          // Rays per hit pixel per soft light, and the share of (contributing) soft pairs refined.
          {"soft_rays_per_pair", s.soft_pairs ? static_cast<double>(s.soft_shadow_rays) / s.soft_pairs : 0.0},
          {"soft_refined_share", s.soft_contributing_pairs
                                     ? static_cast<double>(s.soft_refined_pairs) / s.soft_contributing_pairs
                                     : 0.0},
          // Scene time (a moving scene): frames traced at their scene time, the acceleration-structure updates
          // that moved the tracer there (total, and per such frame).
          // App-moved nodes (NodeTransform): received, applied, and each reason to drop one.
          {"node_transforms_received", s.node_transforms_received},
          {"node_transforms_applied", s.node_transforms_applied},
          {"node_transforms_dropped_unknown_node", s.node_transforms_dropped_unknown_node},
          {"node_transforms_dropped_out_of_order", s.node_transforms_dropped_out_of_order},
          {"node_transforms_dropped_late", s.node_transforms_dropped_late},
          {"frames_at_scene_time", s.frames_at_scene_time},
          {"scene_update_ms", s.scene_update_ms},
          {"scene_update_ms_per_frame",
           s.frames_at_scene_time ? s.scene_update_ms / static_cast<double>(s.frames_at_scene_time) : 0.0},
          {"trace_ms", s.trace_ms},
          // The traces' GPU time (Vulkan timestamps, summed; 0 with Embree). trace_ms less this is the host's share
          // (set-up, submission, readback); the timestamps also count time the GPU spent on other processes' work.
          {"trace_gpu_ms", s.trace_gpu_ms},
          {"encode_ms", s.encode_ms}};
}

}  // namespace dhr::server
