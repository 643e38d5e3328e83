#include "session/metrics_text.hpp"

#include <cstdio>

namespace dhr::server {
namespace {

void header(std::string& out, const char* name, const char* type, const char* help) {
  out += "# HELP ";
  out += name;
  out += ' ';
  out += help;
  out += "\n# TYPE ";
  out += name;
  out += ' ';
  out += type;
  out += '\n';
}

void sample(std::string& out, const std::string& name, double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  out += name;
  out += ' ';
  out += text;
  out += '\n';
}

void metric(std::string& out, const char* name, const char* type, const char* help, double value) {
  header(out, name, type, help);
  sample(out, name, value);
}

void histogram(std::string& out, const char* name, const char* help, const LatencyHistogram& h) {
  header(out, name, "histogram", help);
  uint64_t cumulative = 0;
  for (size_t i = 0; i < LatencyHistogram::kBoundsMs.size(); ++i) {
    cumulative += h.counts[i];
    char le[32];
    std::snprintf(le, sizeof le, "%g", LatencyHistogram::kBoundsMs[i]);
    sample(out, std::string(name) + "_bucket{le=\"" + le + "\"}", static_cast<double>(cumulative));
  }
  sample(out, std::string(name) + "_bucket{le=\"+Inf\"}", static_cast<double>(h.count));
  sample(out, std::string(name) + "_sum", h.sum_ms);
  sample(out, std::string(name) + "_count", static_cast<double>(h.count));
}

}  // namespace

std::string prometheus_text(const ServiceStats& s) {
  std::string out;
  out.reserve(4096);
  metric(out, "dhr_sessions_active", "gauge", "Sessions open now.", static_cast<double>(s.sessions_active));
  metric(out, "dhr_sessions_opened_total", "counter", "Sessions opened (Welcome sent).",
         static_cast<double>(s.sessions_opened));
  metric(out, "dhr_sessions_timed_out_total", "counter", "Sessions closed because the client went silent.",
         static_cast<double>(s.sessions_timed_out));
  metric(out, "dhr_sessions_rate_capped", "gauge", "Sessions whose trace rate is capped now (rate control).",
         static_cast<double>(s.sessions_rate_capped));
  metric(out, "dhr_frames_traced_total", "counter", "Session frames traced and sent (both eyes).",
         static_cast<double>(s.frames_traced));
  metric(out, "dhr_frames_at_scene_time_total", "counter",
         "Frames traced and sent after moving the scene to their scene time (a moving scene).",
         static_cast<double>(s.frames_at_scene_time));
  metric(out, "dhr_scene_update_ms_total", "counter",
         "Acceleration-structure updates that moved the scene to those frames' scene times, milliseconds.",
         s.scene_update_ms);
  metric(out, "dhr_scene_update_ms_per_frame", "gauge", "Mean scene update per frame traced at its scene time, ms.",
         s.frames_at_scene_time ? s.scene_update_ms / static_cast<double>(s.frames_at_scene_time) : 0.0);
  metric(out, "dhr_node_transforms_applied_total", "counter", "App node transforms accepted (applied from their time).",
         static_cast<double>(s.node_transforms_applied));
  header(out, "dhr_node_transforms_dropped_total", "counter", "App node transforms dropped, by reason.");
  const std::pair<const char*, uint64_t> node_drops[] = {{"unknown_node", s.node_transforms_dropped_unknown_node},
                                                         {"out_of_order", s.node_transforms_dropped_out_of_order},
                                                         {"late", s.node_transforms_dropped_late}};
  for (const auto& [reason, count] : node_drops) {
    sample(out, std::string("dhr_node_transforms_dropped_total{reason=\"") + reason + "\"}",
           static_cast<double>(count));
  }
  metric(out, "dhr_poses_received_total", "counter", "Pose updates received.", static_cast<double>(s.poses_received));
  metric(out, "dhr_poses_superseded_total", "counter", "Poses replaced by a newer one before being traced.",
         static_cast<double>(s.poses_superseded));
  metric(out, "dhr_rays_total", "counter", "Rays traced (primary and shadow).", static_cast<double>(s.rays));
  metric(out, "dhr_reused_pixels_total", "counter", "Pixels taken whole from an earlier trace (--reuse on).",
         static_cast<double>(s.reused_pixels));
  metric(out, "dhr_reused_pairs_total", "counter",
         "Pixel-light pairs answered from an earlier trace instead of a shadow ray (--reuse on).",
         static_cast<double>(s.reused_pairs));
  metric(out, "dhr_bytes_sent_total", "counter", "Bytes of every datagram sent, headers included.",
         static_cast<double>(s.bytes_sent));
  metric(out, "dhr_datagrams_sent_total", "counter", "Datagrams sent.", static_cast<double>(s.datagrams_sent));
  metric(out, "dhr_datagrams_received_total", "counter", "Datagrams received.", static_cast<double>(s.datagrams_received));
  header(out, "dhr_datagrams_dropped_total", "counter", "Datagrams dropped, by reason.");
  const std::pair<const char*, uint64_t> reasons[] = {
      {"decode_error", s.decode_errors.total_errors() - s.decode_errors[DecodeError::kWrongVersion]},
      {"wrong_version", s.wrong_version},
      {"unknown_token", s.unknown_token},       {"wrong_peer", s.wrong_peer},
      {"unexpected_type", s.unexpected_type},   {"auth_failed", s.auth_failed},
      {"replayed", s.replayed},                 {"unauthenticated", s.unauthenticated},
      {"hello_replayed", s.hellos_replayed},     {"paced_shed", s.datagrams_shed},
  };
  for (const auto& [reason, count] : reasons) {
    sample(out, std::string("dhr_datagrams_dropped_total{reason=\"") + reason + "\"}", static_cast<double>(count));
  }
  metric(out, "dhr_auth_failures_total", "counter",
         "Datagrams whose tag or seal did not verify, plain ones where a key is required, and replayed Hellos.",
         static_cast<double>(s.auth_failed + s.unauthenticated + s.hellos_replayed));
  metric(out, "dhr_trace_errors_total", "counter", "Frames not sent: the tracer or the encoder failed.",
         static_cast<double>(s.trace_errors));
  histogram(out, "dhr_trace_ms", "Trace time per eye, milliseconds.", s.trace_hist);
  histogram(out, "dhr_response_ms", "Pose received to its frame's last datagram sent (or queued for pacing), milliseconds.",
            s.response_hist);
  return out;
}

}  // namespace dhr::server
