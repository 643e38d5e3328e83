// VisibilityService under bad input and over time: wrong token / peer / version, truncated and
// misdirected datagrams, rejected Hellos, heartbeats, timeouts, Byes, a Hello flood, concurrent use.
#include "service_test_rig.hpp"

#include <thread>

namespace dhr::server {
namespace {

using namespace test_rig;

TEST_F(VisibilityServiceTest, BadDatagramsAreCountedAndDropped) {
  const uint64_t t = connect(peer(1), 1);
  const auto views = bookmark_views(0);
  PoseUpdate pose;
  pose.frame = 1;
  pose.views = views;
  // Unknown token: Bye(unknown session) with that token, no state change.
  send(Datagram{t + 1, 0, pose}, peer(1));
  // Known token from another address: dropped silently.
  send(Datagram{t, 0, pose}, peer(2));
  send(Datagram{t, 0, pose}, peer(1, 5001));
  // Truncated and garbage.
  std::vector<uint8_t> bytes = encode_datagram(Datagram{t, 0, pose});
  bytes.resize(bytes.size() - 1);
  send_raw(bytes, peer(1));
  send_raw({1, 2, 3}, peer(1));
  // Another protocol version's Hello: Bye(version mismatch).
  std::vector<uint8_t> v2 = encode_datagram(Datagram{0, 0, make_hello(5)});
  v2[4] = kProtocolVersion + 1;
  send_raw(v2, peer(3));
  // A server-to-client message from the client: dropped.
  Welcome welcome;
  welcome.buffer_width = 72;
  welcome.buffer_height = 54;
  send(Datagram{t, 0, welcome}, peer(1));

  EXPECT_EQ(service_->process_pending(), 0u);
  auto sent = drain();
  const auto to_1 = byes_of(sent[peer(1)]);
  ASSERT_EQ(to_1.size(), 1u);
  EXPECT_EQ(to_1[0].reason, ByeReason::kUnknownSession);
  EXPECT_EQ(sent[peer(1)][0].session_token, t + 1);
  EXPECT_TRUE(sent[peer(2)].empty());
  EXPECT_TRUE(sent[peer(1, 5001)].empty());
  const auto to_3 = byes_of(sent[peer(3)]);
  ASSERT_EQ(to_3.size(), 1u);
  EXPECT_EQ(to_3[0].reason, ByeReason::kVersionMismatch);

  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.unknown_token, 1u);
  EXPECT_EQ(s.wrong_peer, 2u);
  EXPECT_EQ(s.decode_errors[DecodeError::kTruncated], 2u);
  EXPECT_EQ(s.decode_errors[DecodeError::kWrongVersion], 1u);
  EXPECT_EQ(s.wrong_version, 1u);
  EXPECT_EQ(s.unexpected_type, 1u);
  EXPECT_EQ(s.datagrams_rejected, 7u);
  EXPECT_EQ(s.poses_received, 0u);
  EXPECT_EQ(service_->session_count(), 1u);
  // The session is unharmed: its next pose is traced.
  send_pose(t, peer(1), 1, views);
  EXPECT_EQ(service_->process_pending(), 1u);
}

TEST_F(VisibilityServiceTest, UnacceptableHellosGetBye) {
  Hello other_scene = make_hello(1);
  other_scene.scene_id = "living_room";
  send(Datagram{0, 0, other_scene}, peer(1));
  Hello no_codec = make_hello(2);
  no_codec.capabilities = 0;
  send(Datagram{0, 0, no_codec}, peer(2));
  Hello file_name = make_hello(3);
  file_name.scene_id = "assets/scenes/default_room.gltf";  // a path with the served stem is fine
  send(Datagram{0, 0, file_name}, peer(3));
  auto sent = drain();
  ASSERT_EQ(byes_of(sent[peer(1)]).size(), 1u);
  EXPECT_EQ(byes_of(sent[peer(1)])[0].reason, ByeReason::kUnknownScene);
  EXPECT_EQ(sent[peer(1)][0].session_token, 0u);
  ASSERT_EQ(byes_of(sent[peer(2)]).size(), 1u);
  EXPECT_EQ(byes_of(sent[peer(2)])[0].reason, ByeReason::kBadHello);
  ASSERT_EQ(sent[peer(3)].size(), 1u);
  EXPECT_TRUE(std::holds_alternative<Welcome>(sent[peer(3)][0].message));
  EXPECT_EQ(service_->session_count(), 1u);
  EXPECT_EQ(service_->stats().hellos_rejected, 2u);
  EXPECT_TRUE(scene_id_matches("", "x"));
  EXPECT_TRUE(scene_id_matches("x.glb", "x"));
  EXPECT_FALSE(scene_id_matches("x.glb", "y"));
  EXPECT_FALSE(scene_id_matches(".x", "x"));
}

TEST_F(VisibilityServiceTest, TimeoutSendsByeOnceAndHeartbeatsFlow) {
  const uint64_t t = connect(peer(1), 1);
  // A client Heartbeat is echoed at once.
  Heartbeat hb;
  hb.send_time_ns = 123456;
  send(Datagram{t, 0, hb}, peer(1));
  auto sent = drain();
  ASSERT_EQ(sent[peer(1)].size(), 1u);
  const auto* echo = std::get_if<Heartbeat>(&sent[peer(1)][0].message);
  ASSERT_NE(echo, nullptr);
  EXPECT_EQ(echo->echo_time_ns, 123456);
  EXPECT_EQ(echo->echo_delay_ns, 0);
  EXPECT_EQ(echo->send_time_ns, clock_.now_ns());
  // Then one Heartbeat per interval from tick(), echo delay growing with the time held.
  clock_.advance_ns(config_.heartbeat_interval_ns);
  service_->tick();
  service_->tick();
  sent = drain();
  ASSERT_EQ(sent[peer(1)].size(), 1u);
  const auto* periodic = std::get_if<Heartbeat>(&sent[peer(1)][0].message);
  ASSERT_NE(periodic, nullptr);
  EXPECT_EQ(periodic->echo_delay_ns, config_.heartbeat_interval_ns);
  // Silence past the timeout: one Bye(timeout), then nothing.
  clock_.advance_ns(config_.session_timeout_ns);
  service_->tick();
  service_->tick();
  clock_.advance_ns(config_.session_timeout_ns);
  service_->tick();
  sent = drain();
  const auto byes = byes_of(sent[peer(1)]);
  ASSERT_EQ(byes.size(), 1u);
  EXPECT_EQ(byes[0].reason, ByeReason::kTimeout);
  EXPECT_EQ(service_->session_count(), 0u);
  EXPECT_EQ(service_->stats().sessions_timed_out, 1u);
  // The old token is now unknown: the client is told to start over.
  send_pose(t, peer(1), 1, bookmark_views(0));
  sent = drain();
  ASSERT_EQ(byes_of(sent[peer(1)]).size(), 1u);
  EXPECT_EQ(byes_of(sent[peer(1)])[0].reason, ByeReason::kUnknownSession);
}

TEST_F(VisibilityServiceTest, ClientByeAndShutdownCloseSessions) {
  const uint64_t a = connect(peer(1), 1);
  connect(peer(2), 1);
  send(Datagram{a, 0, Bye{ByeReason::kNormal}}, peer(1));
  EXPECT_EQ(service_->session_count(), 1u);
  EXPECT_EQ(service_->stats().sessions_closed_by_peer, 1u);
  EXPECT_TRUE(drain()[peer(1)].empty());  // no Bye answers a Bye
  service_->close_all(ByeReason::kShutdown);
  auto sent = drain();
  ASSERT_EQ(byes_of(sent[peer(2)]).size(), 1u);
  EXPECT_EQ(byes_of(sent[peer(2)])[0].reason, ByeReason::kShutdown);
  EXPECT_EQ(service_->session_count(), 0u);
}

TEST_F(VisibilityServiceTest, HelloFloodIsBoundedByMaxSessions) {
  for (uint32_t i = 0; i < 1000; ++i)
    send(Datagram{0, i, make_hello(i + 1)}, net::PeerAddress::ipv4({10, 1, static_cast<uint8_t>(i >> 8), static_cast<uint8_t>(i)}, 6000));
  EXPECT_EQ(service_->session_count(), config_.max_sessions);
  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.sessions_opened, config_.max_sessions);
  EXPECT_EQ(s.hellos_rejected, 1000u - config_.max_sessions);
  // Rejections are answered at most max_unsolicited_replies_per_second times (same virtual second).
  EXPECT_EQ(s.byes_sent, config_.max_unsolicited_replies_per_second);
  EXPECT_EQ(s.replies_suppressed, 1000u - config_.max_sessions - config_.max_unsolicited_replies_per_second);
  size_t byes = 0;
  for (const auto& [to, datagrams] : drain()) byes += byes_of(datagrams).size();
  EXPECT_EQ(byes, config_.max_unsolicited_replies_per_second);
  // Poses from a flood of unknown tokens leave nothing pending.
  PoseUpdate pose;
  pose.frame = 1;
  pose.views = bookmark_views(0);
  for (uint64_t i = 0; i < 1000; ++i) send(Datagram{0x1000 + i, 0, pose}, peer(9));
  EXPECT_EQ(service_->process_pending(), 0u);
}

TEST_F(VisibilityServiceTest, ConcurrentDatagramsWhileTracing) {
  Welcome w;
  const uint64_t t = connect(peer(1), 1, &w);
  std::atomic<bool> done{false};
  std::thread worker([&] {
    while (!done.load()) service_->process_pending();
  });
  std::array<View, 2> last{};
  for (uint64_t f = 1; f <= 30; ++f) {
    last = send_pose(t, peer(1), f, bookmark_views(f % 3, 0.01 * static_cast<double>(f)));
    Heartbeat hb;
    hb.send_time_ns = static_cast<int64_t>(f);
    send(Datagram{t, 0, hb}, peer(1));
    service_->tick();
  }
  done.store(true);
  worker.join();
  service_->process_pending();
  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.poses_received, 30u);
  EXPECT_EQ(s.frames_traced + s.poses_superseded, 30u);
  EXPECT_EQ(s.trace_errors, 0u);
  ASSERT_EQ(service_->sessions().size(), 1u);
  EXPECT_EQ(service_->sessions()[0].newest_frame_traced, 30u);
  const auto json = to_json(s);
  EXPECT_EQ(json.at("poses_received").get<uint64_t>(), 30u);
}

}  // namespace
}  // namespace dhr::server
