// VisibilityService over a SimulatedLink and a VirtualClock, with the real Embree tracer on the default
// room: handshake, sessions, pose handling, exact reassembly, fewer lights, prediction, concurrent workers,
// fair turns.
#include "service_test_rig.hpp"

#include <atomic>
#include <set>
#include <thread>

namespace dhr::server {
namespace {

using namespace test_rig;

TEST_F(VisibilityServiceTest, HandshakeGivesTheNegotiatedSession) {
  Welcome w;
  const uint64_t token = connect(peer(1), 77, &w);
  EXPECT_NE(token, 0u);
  EXPECT_EQ(w.client_nonce, 77u);
  EXPECT_EQ(w.buffer_width, kEyeW + 2 * kGuardX);
  EXPECT_EQ(w.buffer_height, kEyeH + 2 * kGuardY);
  EXPECT_EQ(w.guard_x, kGuardX);
  EXPECT_EQ(w.guard_y, kGuardY);
  const uint32_t lights = shared_scene().tracer->light_count();
  ASSERT_GE(lights, 2u);
  EXPECT_EQ(w.light_count, lights);
  EXPECT_EQ(w.mask_bits, mask_width_for_light_count(lights));
  EXPECT_EQ(w.scene_hash, config_.scene_hash);
  EXPECT_EQ(w.heartbeat_interval_ms, 1000);
  EXPECT_EQ(w.session_timeout_ms, 5000u);
  EXPECT_EQ(w.capabilities, kCapabilityLz4RowShards);
  EXPECT_EQ(service_->session_count(), 1u);
  // A repeated Hello (same address and nonce) gets the same Welcome, no new session.
  EXPECT_EQ(connect(peer(1), 77), token);
  EXPECT_EQ(service_->session_count(), 1u);
  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.hellos, 2u);
  EXPECT_EQ(s.hellos_repeated, 1u);
  EXPECT_EQ(s.sessions_opened, 1u);
  // A new nonce from the same address replaces the session.
  const uint64_t token2 = connect(peer(1), 78);
  EXPECT_NE(token2, token);
  EXPECT_EQ(service_->session_count(), 1u);
  EXPECT_EQ(service_->stats().sessions_replaced, 1u);
}

TEST_F(VisibilityServiceTest, SceneHashIsDeterministicAndContentSensitive) {
  Scene copy = shared_scene().scene;
  EXPECT_EQ(scene_content_hash(copy), config_.scene_hash);
  copy.lights[0].intensity *= 2.0f;
  EXPECT_NE(scene_content_hash(copy), config_.scene_hash);
}

TEST_F(VisibilityServiceTest, TwoSessionsGetDistinctTokensAndTheirOwnFrames) {
  Welcome wa, wb;
  const uint64_t a = connect(peer(1), 1, &wa);
  const uint64_t b = connect(peer(2), 1, &wb);  // same nonce, other address: another session
  ASSERT_NE(a, 0u);
  ASSERT_NE(b, 0u);
  EXPECT_NE(a, b);
  EXPECT_EQ(service_->session_count(), 2u);
  const auto va = send_pose(a, peer(1), 10, bookmark_views(0));
  const auto vb = send_pose(b, peer(2), 3, bookmark_views(1));
  EXPECT_EQ(service_->process_pending(), 2u);
  auto sent = drain();
  ASSERT_EQ(sent.size(), 2u);
  for (const Datagram& d : sent[peer(1)]) EXPECT_EQ(d.session_token, a);
  for (const Datagram& d : sent[peer(2)]) EXPECT_EQ(d.session_token, b);
  std::array<View, 2> traced_views;
  const auto got_a = reassemble(wa, shards_of(sent[peer(1)]), 10, &traced_views);
  EXPECT_EQ(got_a[0], trace_directly(va[0]));
  EXPECT_EQ(got_a[1], trace_directly(va[1]));
  EXPECT_EQ(traced_views[0].pose.position, va[0].pose.position);  // the client warps from what was traced
  EXPECT_EQ(traced_views[1].pose.orientation, va[1].pose.orientation);
  const auto got_b = reassemble(wb, shards_of(sent[peer(2)]), 3);
  EXPECT_EQ(got_b[0], trace_directly(vb[0]));
  EXPECT_EQ(got_b[1], trace_directly(vb[1]));
  EXPECT_NE(got_a[0], got_b[0]);
  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.frames_traced, 2u);
  EXPECT_EQ(s.shards_sent, shards_of(sent[peer(1)]).size() + shards_of(sent[peer(2)]).size());
  EXPECT_GT(s.bytes_sent, 0u);
  EXPECT_EQ(s.datagrams_rejected, 0u);
}

TEST_F(VisibilityServiceTest, StaleDuplicateAndSupersededPosesAreNotTraced) {
  Welcome w;
  const uint64_t t = connect(peer(1), 5, &w);
  send_pose(t, peer(1), 5, bookmark_views(0));
  send_pose(t, peer(1), 5, bookmark_views(1));  // duplicate frame number
  send_pose(t, peer(1), 3, bookmark_views(1));  // older
  send_pose(t, peer(1), 6, bookmark_views(1));  // supersedes 5 before it was traced
  const auto v7 = send_pose(t, peer(1), 7, bookmark_views(2));
  EXPECT_EQ(service_->process_pending(), 1u);
  EXPECT_EQ(service_->process_pending(), 0u);  // nothing left
  const auto shards = shards_of(drain()[peer(1)]);
  for (const VisibilityShard& s : shards) EXPECT_EQ(s.frame_number, 7u);
  const auto got = reassemble(w, shards, 7);
  EXPECT_EQ(got[0], trace_directly(v7[0]));
  send_pose(t, peer(1), 7, bookmark_views(0));  // already traced
  EXPECT_EQ(service_->process_pending(), 0u);
  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.poses_received, 6u);
  EXPECT_EQ(s.poses_stale, 3u);
  EXPECT_EQ(s.poses_superseded, 2u);
  EXPECT_EQ(s.frames_traced, 1u);
  ASSERT_EQ(service_->sessions().size(), 1u);
  EXPECT_EQ(service_->sessions()[0].newest_frame_traced, 7u);
}

TEST_F(VisibilityServiceTest, IdenticalPoseIsSkippedUntilTheRefreshInterval) {
  Welcome w;
  const uint64_t t = connect(peer(1), 9, &w);
  const auto views = bookmark_views(0);
  send_pose(t, peer(1), 1, views);
  EXPECT_EQ(service_->process_pending(), 1u);
  const auto first = reassemble(w, shards_of(drain()[peer(1)]), 1);
  send_pose(t, peer(1), 2, views);
  EXPECT_EQ(service_->process_pending(), 0u);
  EXPECT_TRUE(shards_of(drain()[peer(1)]).empty());
  EXPECT_EQ(service_->stats().poses_skipped_identical, 1u);
  // A different pose is traced; so is the same pose once the refresh interval has passed.
  send_pose(t, peer(1), 3, bookmark_views(0, 0.05));
  EXPECT_EQ(service_->process_pending(), 1u);
  send_pose(t, peer(1), 4, bookmark_views(0, 0.05));
  EXPECT_EQ(service_->process_pending(), 0u);
  clock_.advance_ns(config_.identical_refresh_ns);
  send_pose(t, peer(1), 5, bookmark_views(0, 0.05));
  EXPECT_EQ(service_->process_pending(), 1u);
  EXPECT_EQ(service_->stats().poses_skipped_identical, 2u);
  drain();

  // Skip off: the identical pose is traced again, with the same bits.
  config_.skip_identical_pose = false;
  make_service();
  const uint64_t t2 = connect(peer(1), 10, &w);
  send_pose(t2, peer(1), 1, views);
  EXPECT_EQ(service_->process_pending(), 1u);
  const auto again1 = reassemble(w, shards_of(drain()[peer(1)]), 1);
  send_pose(t2, peer(1), 2, views);
  EXPECT_EQ(service_->process_pending(), 1u);
  const auto again2 = reassemble(w, shards_of(drain()[peer(1)]), 2);
  EXPECT_EQ(again1[0], first[0]);
  EXPECT_EQ(again2[0], first[0]);
  EXPECT_EQ(again2[1], first[1]);
  EXPECT_EQ(service_->stats().poses_skipped_identical, 0u);
}

TEST_F(VisibilityServiceTest, FewerLightsKeepTheFirstBits) {
  Welcome w;
  const uint64_t t = connect(peer(1), 3, &w, 1);
  ASSERT_EQ(w.light_count, 1u);
  EXPECT_EQ(w.mask_bits, MaskWidth::k8);
  const auto views = send_pose(t, peer(1), 1, bookmark_views(0));
  EXPECT_EQ(service_->process_pending(), 1u);
  const auto got = reassemble(w, shards_of(drain()[peer(1)]), 1);
  const VisibilityBuffer all = trace_directly(views[0]);
  ASSERT_EQ(got[0].pixel_count(), all.pixel_count());
  EXPECT_EQ(got[0].light_count, 1u);
  size_t lit = 0;
  for (size_t i = 0; i < all.pixel_count(); ++i) {
    ASSERT_EQ(got[0].mask_at(i), all.mask_at(i) & 1u) << i;
    lit += got[0].mask_at(i);
  }
  EXPECT_GT(lit, 0u);  // the test means something: light 0 reaches part of the view
  // Wanting more lights than the scene has gives all of them.
  Welcome w2;
  connect(peer(2), 4, &w2, 32);
  EXPECT_EQ(w2.light_count, shared_scene().tracer->light_count());
}

TEST_F(VisibilityServiceTest, PredictionTracesTheExtrapolatedViews) {
  config_.predict = true;
  config_.predict_horizon_ns = 20'000'000;
  make_service();
  Welcome w;
  const uint64_t t = connect(peer(1), 1, &w);
  const auto v1 = send_pose(t, peer(1), 1, bookmark_views(0, 0.0));
  EXPECT_EQ(service_->process_pending(), 1u);
  drain();
  const auto v2 = send_pose(t, peer(1), 2, bookmark_views(0, 0.02));
  EXPECT_EQ(service_->process_pending(), 1u);
  std::array<View, 2> traced_views;
  const auto got = reassemble(w, shards_of(drain()[peer(1)]), 2, &traced_views);
  PosePredictor reference(config_.predictor);
  reference.add(11'000'000, v1);
  reference.add(22'000'000, v2);
  const PredictedViews expected = reference.predict(22'000'000 + config_.predict_horizon_ns);
  ASSERT_FALSE(expected.fell_back);
  // Moving along +x: the traced eye is ahead of the last pose sent, exactly where the predictor says.
  EXPECT_GT(traced_views[0].pose.position.x, v2[0].pose.position.x + 0.01);
  for (int e = 0; e < 2; ++e) {
    EXPECT_EQ(traced_views[e].pose.position, expected.views[e].pose.position);
    EXPECT_NEAR(glm::dot(traced_views[e].pose.orientation, expected.views[e].pose.orientation), 1.0, 1e-6);
    EXPECT_EQ(got[e], trace_directly(expected.views[e]));
  }
  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.frames_predicted, 2u);
  EXPECT_EQ(s.prediction_fallbacks, 1u);  // one pose is no velocity
  EXPECT_NEAR(s.prediction_horizon_ms, 20.0, 1e-9);
}
// The automatic horizon (RTT + waiting + trace time) is rounded up to the client's frame grid: the result
// is displayed at a client frame, a whole number of frame periods after the pose's display time.
TEST_F(VisibilityServiceTest, AutomaticHorizonLandsOnTheClientFrameGrid) {
  for (const bool grid : {true, false}) {
    SCOPED_TRACE(grid);
    config_.predict = true;
    config_.predict_horizon_ns = -1;
    config_.horizon_on_frame_grid = grid;
    make_service();
    const uint64_t t = connect(peer(1), 1);
    for (uint64_t frame = 1; frame <= 3; ++frame) {  // display times 11 ms apart (send_pose)
      send_pose(t, peer(1), frame, bookmark_views(0, 0.01 * static_cast<double>(frame)));
      clock_.advance_ns(3'000'000);  // the pose waits 3 ms for the worker; no RTT measured yet
      EXPECT_EQ(service_->process_pending(), 1u);
      drain();
    }
    const ServiceStats s = service_->stats();
    EXPECT_EQ(s.frames_predicted, 3u);
    EXPECT_EQ(s.prediction_fallbacks, 1u);  // the first pose has no velocity: horizon 0
    EXPECT_NEAR(s.prediction_horizon_ms, grid ? 22.0 : 6.0, 1e-9);
  }
}

}  // namespace
}  // namespace dhr::server

namespace dhr::server {
namespace {

using namespace test_rig;

TEST_F(VisibilityServiceTest, ConcurrentWorkersTraceEachPendingSessionOnceAndExactly) {
  std::array<Welcome, 4> welcomes;
  std::array<uint64_t, 4> tokens{};
  std::array<std::array<View, 2>, 4> views;
  for (uint8_t i = 0; i < 4; ++i) {
    tokens[i] = connect(peer(static_cast<uint8_t>(10 + i)), 1, &welcomes[i]);
    ASSERT_NE(tokens[i], 0u);
  }
  for (uint8_t i = 0; i < 4; ++i) views[i] = send_pose(tokens[i], peer(static_cast<uint8_t>(10 + i)), 5, bookmark_views(i));
  std::atomic<size_t> traced{0};
  std::thread other([&] { traced += service_->process_pending(); });
  traced += service_->process_pending();
  other.join();
  EXPECT_EQ(traced.load(), 4u);
  EXPECT_EQ(service_->stats().frames_traced, 4u);
  auto sent = drain();
  for (uint8_t i = 0; i < 4; ++i) {
    const auto got = reassemble(welcomes[i], shards_of(sent[peer(static_cast<uint8_t>(10 + i))]), 5);
    EXPECT_EQ(got[0], trace_directly(views[i][0])) << "session " << int{i};
    EXPECT_EQ(got[1], trace_directly(views[i][1])) << "session " << int{i};
  }
}

TEST_F(VisibilityServiceTest, AFloodingSessionIsTracedNoMoreOftenThanAPoliteOne) {
  const uint64_t flood = connect(peer(1), 1);
  const uint64_t polite = connect(peer(2), 1);
  uint64_t frame = 0;
  for (int round = 0; round < 5; ++round) {
    for (int k = 0; k < 10; ++k) {
      ++frame;
      send_pose(flood, peer(1), frame, bookmark_views(static_cast<size_t>(frame)));
    }
    send_pose(polite, peer(2), static_cast<uint64_t>(round + 1), bookmark_views(static_cast<size_t>(round + 7)));
    EXPECT_EQ(service_->process_pending(), 2u);  // one each
  }
  const auto sent = drain();
  auto frames_of = [&](const net::PeerAddress& p) {
    std::set<uint64_t> frames;
    for (const VisibilityShard& s : shards_of(sent.at(p))) frames.insert(s.frame_number);
    return frames.size();
  };
  EXPECT_EQ(frames_of(peer(1)), 5u);
  EXPECT_EQ(frames_of(peer(2)), 5u);
  EXPECT_EQ(service_->stats().poses_superseded, 5u * 9u);
}

// --reuse on (ServiceConfig::reuse): a session walking slowly gets exactly the exhaustive trace's bits every frame,
// and takes pixels from its earlier traces (the stats count them).
TEST_F(VisibilityServiceTest, ReuseGivesTheExhaustiveBitsAndCountsWhatItTook) {
  config_.reuse = true;
  make_service();
  Welcome w;
  const uint64_t t = connect(peer(1), 5, &w);
  for (uint64_t f = 1; f <= 6; ++f) {
    const auto views = send_pose(t, peer(1), f, bookmark_views(0, 0.002 * static_cast<double>(f)));
    EXPECT_EQ(service_->process_pending(), 1u);
    const auto got = reassemble(w, shards_of(drain()[peer(1)]), f);
    for (int e = 0; e < 2; ++e) EXPECT_EQ(got[e], trace_directly(views[e])) << "frame " << f << " eye " << e;
  }
  const ServiceStats s = service_->stats();
  EXPECT_GT(s.reused_pixels, 0u);
  EXPECT_GT(s.reused_pairs, 0u);
}

// With reuse, a session's first trace already takes pixel-light pairs from another session's newest record (the
// scene's view-independent state): the same views give the same bits as the exhaustive trace.
TEST_F(VisibilityServiceTest, ReuseSharesRecordsBetweenSessions) {
  config_.reuse = true;
  make_service();
  Welcome w1, w2;
  const uint64_t t1 = connect(peer(1), 5, &w1);
  const uint64_t t2 = connect(peer(2), 6, &w2);
  const auto views = send_pose(t1, peer(1), 1, bookmark_views(0));
  EXPECT_EQ(service_->process_pending(), 1u);
  drain();
  const uint64_t pairs_before = service_->stats().reused_pairs;
  send_pose(t2, peer(2), 1, bookmark_views(0));
  EXPECT_EQ(service_->process_pending(), 1u);
  const auto got = reassemble(w2, shards_of(drain()[peer(2)]), 1);
  for (int e = 0; e < 2; ++e) EXPECT_EQ(got[e], trace_directly(views[e])) << "eye " << e;
  EXPECT_GT(service_->stats().reused_pairs, pairs_before);
}

// Two workers tracing four sessions that read each other's records while they are replaced: every frame arrives,
// within the reuse rule's bound of the exhaustive trace (the 1e-4 of the pixel-light bits).
TEST_F(VisibilityServiceTest, ReuseWithConcurrentWorkersStaysWithinTheBound) {
  config_.reuse = true;
  make_service();
  std::array<Welcome, 4> welcomes;
  std::array<uint64_t, 4> tokens{};
  for (uint8_t i = 0; i < 4; ++i) tokens[i] = connect(peer(static_cast<uint8_t>(20 + i)), 1, &welcomes[i]);
  uint64_t bits = 0, differing = 0;
  for (uint64_t frame = 1; frame <= 4; ++frame) {
    std::array<std::array<View, 2>, 4> views;
    for (uint8_t i = 0; i < 4; ++i)
      views[i] = send_pose(tokens[i], peer(static_cast<uint8_t>(20 + i)), frame,
                           bookmark_views(i % 2, 0.003 * static_cast<double>(frame + i)));
    std::atomic<size_t> traced{0};
    std::thread other([&] { traced += service_->process_pending(); });
    traced += service_->process_pending();
    other.join();
    EXPECT_EQ(traced.load(), 4u);
    auto sent = drain();
    for (uint8_t i = 0; i < 4; ++i) {
      const auto got = reassemble(welcomes[i], shards_of(sent[peer(static_cast<uint8_t>(20 + i))]), frame);
      for (int e = 0; e < 2; ++e) {
        const VisibilityBuffer exact = trace_directly(views[i][static_cast<size_t>(e)]);
        ASSERT_EQ(got[e].pixel_count(), exact.pixel_count());
        bits += exact.pixel_count() * exact.light_count;
        for (size_t p = 0; p < exact.pixel_count(); ++p)
          differing += static_cast<uint64_t>(__builtin_popcount(got[e].mask_at(p) ^ exact.mask_at(p)));
      }
    }
  }
  EXPECT_LE(static_cast<double>(differing), 1e-4 * static_cast<double>(bits));
  EXPECT_GT(service_->stats().reused_pairs, 0u);
}

}  // namespace
}  // namespace dhr::server
