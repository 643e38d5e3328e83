// prometheus_text: every metric has HELP and TYPE lines, counters and gauges carry the statistics' values,
// drops are split by reason, and the histograms are cumulative with +Inf equal to the count.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "session/metrics_text.hpp"

namespace dhr::server {
namespace {

bool has_line(const std::string& text, const std::string& line) {
  std::istringstream in(text);
  std::string l;
  while (std::getline(in, l))
    if (l == line) return true;
  return false;
}

TEST(MetricsText, CountersGaugesDropsAndCumulativeHistograms) {
  ServiceStats s;
  s.sessions_active = 3;
  s.sessions_opened = 5;
  s.frames_traced = 42;
  s.rays = 123456789;
  s.bytes_sent = 1'000'000;
  s.unknown_token = 7;
  s.auth_failed = 2;
  s.unauthenticated = 1;
  s.hellos_replayed = 4;
  s.decode_errors.add(DecodeError::kTruncated);
  s.decode_errors.add(DecodeError::kWrongVersion);
  s.wrong_version = 1;
  s.frames_at_scene_time = 4;
  s.scene_update_ms = 10.0;
  s.node_transforms_applied = 6;
  s.node_transforms_dropped_late = 2;
  for (const double ms : {0.5, 1.0, 3.0, 3.0, 700.0, 5000.0}) s.trace_hist.add(ms);
  const std::string text = prometheus_text(s);
  EXPECT_TRUE(has_line(text, "# TYPE dhr_sessions_active gauge"));
  EXPECT_TRUE(has_line(text, "dhr_sessions_active 3"));
  EXPECT_TRUE(has_line(text, "dhr_sessions_opened_total 5"));
  EXPECT_TRUE(has_line(text, "dhr_frames_traced_total 42"));
  EXPECT_TRUE(has_line(text, "dhr_rays_total 123456789"));
  EXPECT_TRUE(has_line(text, "dhr_bytes_sent_total 1000000"));
  EXPECT_TRUE(has_line(text, "dhr_datagrams_dropped_total{reason=\"unknown_token\"} 7"));
  EXPECT_TRUE(has_line(text, "dhr_datagrams_dropped_total{reason=\"decode_error\"} 1"));  // the version is apart
  EXPECT_TRUE(has_line(text, "dhr_datagrams_dropped_total{reason=\"wrong_version\"} 1"));
  EXPECT_TRUE(has_line(text, "dhr_auth_failures_total 7"));
  EXPECT_TRUE(has_line(text, "dhr_frames_at_scene_time_total 4"));
  EXPECT_TRUE(has_line(text, "dhr_scene_update_ms_total 10"));
  EXPECT_TRUE(has_line(text, "dhr_scene_update_ms_per_frame 2.5"));
  EXPECT_TRUE(has_line(text, "dhr_node_transforms_applied_total 6"));
  EXPECT_TRUE(has_line(text, "dhr_node_transforms_dropped_total{reason=\"late\"} 2"));
  EXPECT_TRUE(has_line(text, "dhr_node_transforms_dropped_total{reason=\"unknown_node\"} 0"));
  EXPECT_TRUE(has_line(text, "# TYPE dhr_trace_ms histogram"));
  EXPECT_TRUE(has_line(text, "dhr_trace_ms_bucket{le=\"1\"} 2"));
  EXPECT_TRUE(has_line(text, "dhr_trace_ms_bucket{le=\"2\"} 2"));
  EXPECT_TRUE(has_line(text, "dhr_trace_ms_bucket{le=\"5\"} 4"));
  EXPECT_TRUE(has_line(text, "dhr_trace_ms_bucket{le=\"500\"} 4"));
  EXPECT_TRUE(has_line(text, "dhr_trace_ms_bucket{le=\"1000\"} 5"));
  EXPECT_TRUE(has_line(text, "dhr_trace_ms_bucket{le=\"+Inf\"} 6"));
  EXPECT_TRUE(has_line(text, "dhr_trace_ms_sum 5707.5"));
  EXPECT_TRUE(has_line(text, "dhr_trace_ms_count 6"));
  EXPECT_TRUE(has_line(text, "dhr_response_ms_count 0"));
  // Every sample line belongs to a metric announced by a TYPE line.
  std::istringstream in(text);
  std::string line, typed;
  while (std::getline(in, line)) {
    if (line.rfind("# TYPE ", 0) == 0) {
      typed = line.substr(7, line.find(' ', 7) - 7);
    } else if (line.rfind('#', 0) != 0) {
      EXPECT_EQ(line.rfind(typed, 0), 0u) << line << " after TYPE " << typed;
    }
  }
}

}  // namespace
}  // namespace dhr::server
