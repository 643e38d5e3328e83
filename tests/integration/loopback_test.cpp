// Server and client together over real UDP on 127.0.0.1: the real VisibilityService with the Embree tracer
// on the default room, the real VisibilityClient on a ClientEndpoint, a 90 Hz pose sequence. Checks what
// the render loop gets (newest data, frame numbers never going back, every complete buffer bit-identical to
// the tracer's direct output for the traced view, partial buffers exact on their valid rows), bounded
// memory, and that the client's counters add up with what the server and the impairment layer did.
// Nothing asserts on time; sleeps only pace the loop.
#include "loopback_rig.hpp"
#include "wait_until.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cmath>
#include <map>
#include <thread>

namespace dhr::integration {
namespace {

using net::test::wait_until;

struct Verified {
  size_t complete = 0;
  size_t partial = 0;
};

// Every take against the tracer's direct output for the view the server decoded for that frame and eye.
Verified verify_takes(const RunRecord& record) {
  Verified v;
  std::map<std::pair<uint64_t, int>, VisibilityBuffer> references;
  for (const Take& take : record.takes) {
    const auto views = record.traced_views.find(take.frame);
    EXPECT_NE(views, record.traced_views.end()) << "frame " << take.frame << " was never requested";
    if (views == record.traced_views.end()) continue;
    const View& traced = views->second[static_cast<size_t>(take.eye)];
    const VisibilityFrame& got = take.visibility;
    // The shard's view is the traced one (positions travel as f64, orientations as f32).
    EXPECT_EQ(got.view.pose.position, traced.pose.position) << "frame " << take.frame;
    EXPECT_NEAR(std::abs(glm::dot(got.view.pose.orientation, traced.pose.orientation)), 1.0, 1e-6);
    auto [it, inserted] = references.try_emplace({take.frame, static_cast<int>(take.eye)});
    if (inserted) it->second = reference_trace(traced, record.size);
    const VisibilityBuffer& expected = it->second;
    if (got.complete) {
      ++v.complete;
      EXPECT_EQ(got.rows_valid, expected.height);
      EXPECT_TRUE(got.buffer == expected) << "frame " << take.frame << " eye " << static_cast<int>(take.eye)
                                          << ": complete buffer differs from the tracer's output";
    } else {
      ++v.partial;
      EXPECT_EQ(got.buffer.width, expected.width);
      EXPECT_EQ(got.buffer.height, expected.height);
      if (got.buffer.width != expected.width || got.buffer.height != expected.height) continue;
      for (uint32_t y = 0; y < expected.height; ++y) {
        if (!got.row_valid[y]) continue;
        for (uint32_t x = 0; x < expected.width; ++x)
          if (got.buffer.get(x, y) != expected.get(x, y)) {
            ADD_FAILURE() << "frame " << take.frame << " row " << y << " marked valid but differs at x=" << x;
            break;
          }
      }
    }
  }
  return v;
}

// One JSON line for the docs (printed, never asserted).
void print_summary(const char* name, const RunRecord& record, const Verified& verified,
                   const client::ClientNetStats& c, const server::ServiceStats& s) {
  std::printf(
      "{\"test\": \"%s\", \"eye\": \"%ux%u+%u,%u\", \"frames_sent\": %llu, \"frames_traced\": %llu, "
      "\"shards_sent\": %llu, \"shards_received\": %llu, \"shards_late\": %llu, \"shards_duplicate\": %llu, "
      "\"frames_completed\": %llu, \"frames_evicted\": %llu, \"frames_superseded\": %llu, "
      "\"published_complete\": %llu, \"published_partial\": %llu, \"takes_complete\": %zu, "
      "\"takes_partial\": %zu, \"response_ms\": {\"count\": %llu, \"min\": %.2f, \"mean\": %.2f, "
      "\"max\": %.2f}, \"clock_offset_us\": %.1f, \"clock_uncertainty_us\": %.1f, "
      "\"reassembler_bytes\": %zu}\n",
      name, record.size.width, record.size.height, record.size.guard_x, record.size.guard_y,
      static_cast<unsigned long long>(record.last_frame_sent), static_cast<unsigned long long>(s.frames_traced),
      static_cast<unsigned long long>(s.shards_sent), static_cast<unsigned long long>(c.shards_received),
      static_cast<unsigned long long>(c.shards_late), static_cast<unsigned long long>(c.shards_duplicate),
      static_cast<unsigned long long>(c.frames_completed), static_cast<unsigned long long>(c.frames_evicted),
      static_cast<unsigned long long>(c.frames_superseded),
      static_cast<unsigned long long>(c.frames_published_complete),
      static_cast<unsigned long long>(c.frames_published_partial), verified.complete, verified.partial,
      static_cast<unsigned long long>(c.response.count), static_cast<double>(c.response.min_ns) / 1e6,
      static_cast<double>(c.response.mean_ns()) / 1e6, static_cast<double>(c.response.max_ns) / 1e6,
      static_cast<double>(c.clock_offset_ns) / 1e3, static_cast<double>(c.clock_uncertainty_ns) / 1e3,
      c.reassembler_memory_bytes);
}

// The last take of each eye.
std::array<const Take*, 2> last_takes(const RunRecord& record) {
  std::array<const Take*, 2> last{nullptr, nullptr};
  for (const Take& t : record.takes) last[static_cast<size_t>(t.eye)] = &t;
  return last;
}

TEST(Loopback, CleanNetworkDeliversEveryTracedFrameBitExact) {
  TracedScene& scene = TracedScene::get();
  LoopbackServer server(*scene.tracer);
  client::UdpVisibilityClient client;
  RunRecord record;  // 64x48 per eye
  client.connect(client_config(record.size), "127.0.0.1", server.port());

  constexpr uint64_t kFrames = 180;
  run_frames(client, kFrames, record);
  ASSERT_FALSE(client.client().failed()) << client.client().failure();
  ASSERT_EQ(record.last_frame_sent, kFrames);
  // The newest pose is never superseded, so the server traces it; wait until both eyes are in.
  ASSERT_TRUE(wait_until([&] {
    const client::ClientNetStats s = client.client().stats();
    return s.newest_frame_complete[0] == kFrames && s.newest_frame_complete[1] == kFrames;
  })) << "the last frame never completed";
  idle_frames(client, 50 * net::kNsPerMs, record);
  server.stop();
  ASSERT_TRUE(wait_until([&] { return client.udp_counters().datagrams_received >= server.udp_counters().datagrams_sent; }));

  // What the render loop got.
  EXPECT_EQ(record.monotonic_violations, 0u);
  const auto last = last_takes(record);
  for (const Take* t : last) {
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(t->frame, kFrames);
    EXPECT_TRUE(t->visibility.complete);
  }
  const Verified verified = verify_takes(record);
  EXPECT_GT(verified.complete, 20u);
  EXPECT_EQ(verified.partial, 0u);

  // Counters: loopback UDP at this rate (a few kB per frame, far below the 1 MiB socket buffers) loses
  // and duplicates nothing, so everything matches exactly.
  const client::ClientNetStats c = client.client().stats();
  const server::ServiceStats s = server.service().stats();
  const net::UdpCounters server_udp = server.udp_counters();
  EXPECT_EQ(server_udp.datagrams_sent, s.datagrams_sent);
  EXPECT_EQ(client.udp_counters().datagrams_received, server_udp.datagrams_sent);
  EXPECT_EQ(c.datagrams_received, server_udp.datagrams_sent);
  EXPECT_EQ(c.datagrams_rejected + c.datagrams_foreign + c.datagrams_unexpected, 0u);
  EXPECT_EQ(c.server_datagrams_unique, s.datagrams_sent);
  EXPECT_EQ(c.server_datagrams_duplicate, 0u);
  EXPECT_EQ(c.server_datagrams_missing, 0u);
  EXPECT_EQ(c.shards_received, s.shards_sent);
  EXPECT_EQ(c.shards_late + c.shards_duplicate + c.shards_rejected, 0u);
  EXPECT_EQ(c.frames_completed, 2 * s.frames_traced);
  EXPECT_EQ(c.frames_evicted + c.frames_superseded, 0u);
  EXPECT_EQ(c.poses_sent, kFrames);
  EXPECT_EQ(s.poses_received, kFrames);
  EXPECT_EQ(s.datagrams_rejected, 0u);
  EXPECT_EQ(c.sessions_started, 1u);
  EXPECT_EQ(c.sessions_restarted, 0u);
  // Every traced frame has a response time; clocks are the same steady clock, so the estimated offset
  // must lie within its own causality bound of 0.
  EXPECT_EQ(c.response.count, s.frames_traced);
  EXPECT_TRUE(client.client().response_ns(kFrames).has_value());
  ASSERT_TRUE(c.clock_offset_valid);
  EXPECT_LE(std::abs(c.clock_offset_ns), c.clock_uncertainty_ns);
  // Bounded memory.
  EXPECT_GT(c.reassembler_memory_bytes, 0u);
  EXPECT_LE(c.reassembler_memory_bytes, client.client().memory_bound_bytes());
  print_summary("clean", record, verified, c, s);
}

// codec_v2: the server codes with v2 (against acknowledged references), in shards small enough that losses
// leave partial frames; else v1. Either way every bit shown as valid equals the traced bits.
void run_impaired(bool codec_v2) {
  TracedScene& scene = TracedScene::get();
  net::ImpairmentParams impairment;
  impairment.delay_ms = 50.0;
  impairment.jitter_ms = 20.0;
  impairment.loss = 0.3;
  impairment.reorder = 0.05;
  impairment.duplicate = 0.05;
  impairment.seed = 1;
  LoopbackServer server(*scene.tracer, impairment, [codec_v2](server::ServiceConfig& c) {
    c.codec_v2 = codec_v2;
    if (codec_v2) c.encode.max_payload = 160;  // v2 needs far fewer bytes: small shards keep several per eye
  });
  client::UdpVisibilityClient client;
  RunRecord record;
  // Large enough for several shards per eye, so losses leave partial frames.
  record.size = EyeSize{160, 120, 8, 6};
  client.connect(client_config(record.size), "127.0.0.1", server.port());

  constexpr uint64_t kFrames = 270;
  run_frames(client, kFrames, record);
  ASSERT_FALSE(client.client().failed()) << client.client().failure();
  ASSERT_EQ(record.last_frame_sent, kFrames);
  // Let the server trace what is pending and the impairment layer release everything it holds.
  ASSERT_TRUE(wait_until([&] {
    const auto sessions = server.service().sessions();
    return sessions.size() == 1 && sessions[0].newest_frame_traced == kFrames;
  }));
  server.stop();
  const net::ImpairedSenderStats imp = server.impairment_stats().value();
  ASSERT_EQ(imp.in_flight, 0u);
  ASSERT_TRUE(wait_until([&] { return client.udp_counters().datagrams_received >= server.udp_counters().datagrams_sent; }));
  idle_frames(client, 100 * net::kNsPerMs, record);  // incomplete last frames go quiet and are published

  const client::ClientNetStats c = client.client().stats();
  const server::ServiceStats s = server.service().stats();
  // The impairment layer saw every datagram the service sent and forwarded every copy it scheduled;
  // the socket sent them all and loopback delivered them all (exact: see the clean test).
  EXPECT_EQ(imp.model.sent, s.datagrams_sent);
  EXPECT_EQ(imp.forward_refused + imp.dropped_overflow, 0u);
  EXPECT_EQ(imp.forwarded, imp.model.deliveries);
  EXPECT_EQ(server.udp_counters().datagrams_sent, imp.forwarded);
  EXPECT_EQ(client.udp_counters().datagrams_received, imp.forwarded);
  EXPECT_EQ(c.datagrams_received, imp.forwarded);
  EXPECT_EQ(c.datagrams_rejected + c.datagrams_foreign + c.datagrams_unexpected, 0u);
  // From the server's sequence numbers the client sees exactly what the impairment did.
  EXPECT_GT(imp.model.lost, 0u);
  EXPECT_GT(imp.model.duplicated, 0u);
  EXPECT_GT(imp.model.reordered, 0u);
  EXPECT_EQ(c.server_datagrams_unique + imp.model.lost, imp.model.sent);
  EXPECT_EQ(c.server_datagrams_duplicate, imp.model.duplicated);
  // Gaps are the losses the client can see: all but lost Welcomes before the adopted one (the window
  // starts there) and losses after the newest datagram that arrived. Each of those runs is a streak of
  // consecutive 30 % losses: 10 or more together has a probability of ~1e-5.
  EXPECT_LE(c.server_datagrams_missing, imp.model.lost);
  EXPECT_GE(c.server_datagrams_missing + 10, imp.model.lost);
  // Every datagram received is accounted for by type.
  EXPECT_EQ(c.datagrams_handled,
            c.shards_received + c.heartbeats_received + c.sessions_started + c.welcomes_repeated + c.byes_received);
  EXPECT_LE(c.shards_received, s.shards_sent + imp.model.duplicated);
  EXPECT_EQ(c.shards_received, c.shards_accepted + c.shards_late + c.shards_duplicate + c.shards_rejected);
  EXPECT_EQ(c.shards_rejected, 0u);
  EXPECT_EQ(c.sessions_started, 1u);

  // What the render loop got: never older, the newest that arrived, exact where marked valid.
  EXPECT_EQ(record.monotonic_violations, 0u);
  const auto last = last_takes(record);
  for (size_t e = 0; e < 2; ++e) {
    ASSERT_NE(last[e], nullptr);
    ASSERT_TRUE(c.newest_frame_received[e].has_value());
    EXPECT_EQ(last[e]->frame, *c.newest_frame_received[e]) << "eye " << e;
  }
  const Verified verified = verify_takes(record);
  EXPECT_GT(verified.complete, 0u);
  EXPECT_GT(verified.partial, 0u);
  EXPECT_EQ(c.frames_published_partial + c.frames_published_complete, c.frames_taken + c.frames_overwritten);
  EXPECT_LE(c.reassembler_memory_bytes, client.client().memory_bound_bytes());
  std::printf("{\"impairment\": {\"sent\": %llu, \"lost\": %llu, \"duplicated\": %llu, \"reordered\": %llu}, "
              "\"client\": {\"unique\": %llu, \"duplicates\": %llu, \"missing\": %llu}}\n",
              static_cast<unsigned long long>(imp.model.sent), static_cast<unsigned long long>(imp.model.lost),
              static_cast<unsigned long long>(imp.model.duplicated), static_cast<unsigned long long>(imp.model.reordered),
              static_cast<unsigned long long>(c.server_datagrams_unique),
              static_cast<unsigned long long>(c.server_datagrams_duplicate),
              static_cast<unsigned long long>(c.server_datagrams_missing));
  if (codec_v2) {
    EXPECT_GT(s.eyes_coded_v2_inter, 0u);  // acknowledgements arrived and were used
    EXPECT_GT(s.eyes_coded_v2_intra, 0u);
  } else {
    EXPECT_EQ(s.eyes_coded_v2_inter + s.eyes_coded_v2_intra, 0u);
  }
  print_summary(codec_v2 ? "impaired_v2" : "impaired_v1", record, verified, c, s);
}

TEST(Loopback, ImpairedServerLinkCountersMatchTheImpairmentLayer) { run_impaired(false); }

// Codec v2 under 30 % loss, jitter, reordering and duplicates: inter shards decode only against frames the
// client acknowledged, so none is rejected for a missing reference and no wrong bit is shown.
TEST(Loopback, ImpairedLinkWithCodecV2ShowsNoWrongBit) { run_impaired(true); }

}  // namespace
}  // namespace dhr::integration
