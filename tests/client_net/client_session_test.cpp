// VisibilityClient session: handshake, nonce matching, Hello retry and give-up, refusals, restarts on
// timeout and Bye(unknown session), heartbeats, and which poses are sent.
#include "client_harness.hpp"

#include <set>
#include <stdexcept>

namespace dhr::client::test {
namespace {

TEST(ClientSession, HelloCarriesTheConfigAndWelcomeWithItsNonceConnects) {
  Harness h;
  EXPECT_FALSE(h.client.connected());
  h.client.tick();
  h.run_for(kMs);
  const auto hellos = h.received<Hello>();
  ASSERT_EQ(hellos.size(), 1u);
  EXPECT_NE(hellos[0].client_nonce, 0u);
  EXPECT_EQ(hellos[0].eye_width, kEyeW);
  EXPECT_EQ(hellos[0].eye_height, kEyeH);
  EXPECT_EQ(hellos[0].guard_x, kGuard);
  EXPECT_EQ(hellos[0].guard_y, kGuard);
  EXPECT_EQ(hellos[0].light_count_wanted, kLights);
  EXPECT_EQ(h.from_client[0].datagram.session_token, 0u);

  // A Welcome answering another Hello (other nonce) is ignored.
  h.server_send(h.welcome_for(hellos[0].client_nonce + 1));
  h.run_for(kMs);
  EXPECT_FALSE(h.client.connected());
  EXPECT_EQ(h.client.stats().welcomes_ignored, 1u);

  const Welcome welcome = h.welcome_for(hellos[0].client_nonce);
  h.server_send(welcome);
  h.run_for(kMs);
  ASSERT_TRUE(h.client.connected());
  EXPECT_EQ(h.client.welcome(), welcome);
  EXPECT_FALSE(h.client.failed());
  const ClientNetStats s = h.client.stats();
  EXPECT_EQ(s.sessions_started, 1u);
  EXPECT_EQ(s.hellos_sent, 1u);
  // The first heartbeat goes out with the session token right after connecting.
  h.run_for(kMs);
  ASSERT_FALSE(h.received<Heartbeat>().empty());
  EXPECT_EQ(h.from_client.back().datagram.session_token, kToken);
}

TEST(ClientSession, RetriesHelloWithTheSameNonceThenGivesUp) {
  Harness h;
  h.client.tick();
  h.run_for(6'000 * kMs);
  const auto hellos = h.received<Hello>();
  // Sent at 0, 250, ..., 4750 ms; at 5000 ms the client gives up.
  EXPECT_EQ(hellos.size(), 20u);
  for (const Hello& hello : hellos) EXPECT_EQ(hello.client_nonce, hellos[0].client_nonce);
  EXPECT_TRUE(h.client.failed());
  EXPECT_NE(h.client.failure().find("no Welcome"), std::string::npos) << h.client.failure();
  EXPECT_EQ(h.client.stats().hellos_sent, 20u);
  // Failed is terminal: nothing more is sent.
  const size_t sent = h.from_client.size();
  h.run_for(1'000 * kMs);
  EXPECT_EQ(h.from_client.size(), sent);
  EXPECT_FALSE(h.client.send_pose(FramePose{1, 0, views_for(1)}));
}

// Offline mode: past the give-up time the client keeps sending Hello, the interval doubling up to the cap,
// never fails, and a Welcome still connects.
TEST(ClientSession, KeepRetryingBacksOffAndAWelcomeStillConnects) {
  VisibilityClientConfig config = test_config();
  config.keep_retrying = true;
  config.hello_retry_ns = 250 * kMs;
  config.hello_give_up_ns = 1'000 * kMs;
  config.hello_backoff_max_ns = 2'000 * kMs;
  Harness h(config);
  h.client.tick();
  h.run_for(12'000 * kMs);
  EXPECT_FALSE(h.client.failed());
  std::vector<int64_t> sent;
  for (const auto& d : h.from_client) {
    if (std::holds_alternative<Hello>(d.datagram.message)) sent.push_back(d.receive_ns);
  }
  // 0, 250, 500, 750 ms, then backing off from the give-up time: 1000 ms, and 500, 1000, 2000, 2000, ... ms apart.
  ASSERT_GE(sent.size(), 9u);
  std::vector<int64_t> gaps;
  for (size_t i = 1; i < sent.size(); ++i) gaps.push_back((sent[i] - sent[i - 1]) / kMs);
  EXPECT_EQ(gaps[0], 250);
  EXPECT_EQ(gaps[3], 250);
  EXPECT_EQ(gaps[4], 500);
  EXPECT_EQ(gaps[5], 1000);
  EXPECT_EQ(gaps[6], 2000);
  EXPECT_EQ(gaps.back(), 2000);
  EXPECT_EQ(h.client.stats().hellos_backed_off, sent.size() - 4);
  const auto hellos = h.received<Hello>();
  for (const Hello& hello : hellos) EXPECT_EQ(hello.client_nonce, hellos[0].client_nonce);
  h.server_send(h.welcome_for(hellos[0].client_nonce));
  h.run_for(kMs);
  EXPECT_TRUE(h.client.connected());
}

TEST(ClientSession, AWelcomeAfterARetryStillConnects) {
  Harness h;
  h.client.tick();
  h.run_for(600 * kMs);
  ASSERT_EQ(h.received<Hello>().size(), 3u);
  h.server_send(h.welcome_for(h.received<Hello>()[0].client_nonce));
  h.server_send(h.welcome_for(h.received<Hello>()[0].client_nonce));  // the answer to the retry
  h.run_for(kMs);
  EXPECT_TRUE(h.client.connected());
  const ClientNetStats s = h.client.stats();
  EXPECT_EQ(s.sessions_started, 1u);
  EXPECT_EQ(s.welcomes_repeated, 1u);
}

TEST(ClientSession, ServerRefusalFailsWithTheReason) {
  for (const ByeReason reason : {ByeReason::kBadHello, ByeReason::kUnknownScene}) {
    Harness h;
    h.client.tick();
    h.run_for(kMs);
    h.server_send(Bye{reason}, 0);
    h.run_for(kMs);
    EXPECT_TRUE(h.client.failed());
    EXPECT_NE(h.client.failure().find(to_string(reason)), std::string::npos) << h.client.failure();
  }
}

TEST(ClientSession, AnotherProtocolVersionFailsWithBothVersions) {
  Harness h;
  h.client.tick();
  h.run_for(kMs);
  std::vector<uint8_t> bye = encode_datagram(Datagram{0, 0, Bye{ByeReason::kVersionMismatch}});
  bye[4] = kProtocolVersion + 1;  // the server's version
  h.server_send_raw(bye);
  h.run_for(kMs);
  EXPECT_TRUE(h.client.failed());
  EXPECT_NE(h.client.failure().find("version " + std::to_string(kProtocolVersion + 1)), std::string::npos)
      << h.client.failure();
  EXPECT_EQ(h.client.stats().rejections[DecodeError::kWrongVersion], 1u);
}

TEST(ClientSession, WelcomeThatDoesNotFitTheHelloFails) {
  Harness h;
  h.client.tick();
  h.run_for(kMs);
  Welcome w = h.welcome_for(h.received<Hello>()[0].client_nonce);
  w.buffer_width = kBufW + 2;  // not eye width + 2 * guard
  h.server_send(w);
  h.run_for(kMs);
  EXPECT_TRUE(h.client.failed());
  EXPECT_NE(h.client.failure().find("guard band"), std::string::npos) << h.client.failure();
}

// Soft levels: a client whose scene has no light with an extent does not offer them, and a Welcome granting
// them anyway fails instead of showing level fields as light bits.
TEST(ClientSession, SoftLevelsAreNotOfferedWithoutSoftLightsAndAGrantFails) {
  Harness h;
  h.client.tick();
  h.run_for(kMs);
  const auto hellos = h.received<Hello>();
  ASSERT_EQ(hellos.size(), 1u);
  EXPECT_EQ(hellos[0].capabilities & kCapabilitySoftLevels, 0u);
  Welcome w = h.welcome_for(hellos[0].client_nonce);
  w.capabilities |= kCapabilitySoftLevels;
  w.soft_light_count = 1;
  w.mask_bits = mask_width_for_light_count(w.used_mask_bits());
  h.server_send(w);
  h.run_for(kMs);
  EXPECT_FALSE(h.client.connected());
  EXPECT_TRUE(h.client.failed());
  EXPECT_NE(h.client.failure().find("soft levels"), std::string::npos) << h.client.failure();
}

// A client whose light 0 has an extent offers soft levels and connects when they are granted for exactly that
// light; a Welcome without them (one bit per light) or for another count fails: the client would read the
// fields wrongly.
TEST(ClientSession, SoftLevelsAreOfferedForSoftLightsAndTheGrantMustMatch) {
  VisibilityClientConfig config = test_config();
  config.soft_lights = 1u;  // light 0
  for (const int granted : {1, 0, 2}) {  // soft lights the Welcome grants (0: not granted)
    SCOPED_TRACE("granted " + std::to_string(granted));
    Harness h(config);
    h.client.tick();
    h.run_for(kMs);
    const auto hellos = h.received<Hello>();
    ASSERT_EQ(hellos.size(), 1u);
    EXPECT_NE(hellos[0].capabilities & kCapabilitySoftLevels, 0u);
    Welcome w = h.welcome_for(hellos[0].client_nonce);
    ASSERT_GE(w.light_count, 2u);
    if (granted > 0) w.capabilities |= kCapabilitySoftLevels;
    w.soft_light_count = static_cast<uint8_t>(granted);
    w.mask_bits = mask_width_for_light_count(w.used_mask_bits());
    h.server_send(w);
    h.run_for(kMs);
    EXPECT_EQ(h.client.connected(), granted == 1) << h.client.failure();
    if (granted != 1) {
      EXPECT_NE(h.client.failure().find("soft"), std::string::npos) << h.client.failure();
    }
  }
}

// A client that renders the scene with hash 0x1111222233334444, answered by a Welcome naming `server_hash`.
constexpr uint64_t kClientSceneHash = 0x1111'2222'3333'4444ull;
void answer_with_scene(Harness& h, uint64_t server_hash) {
  h.client.tick();
  h.run_for(kMs);
  Welcome w = h.welcome_for(h.received<Hello>()[0].client_nonce);
  w.scene_hash = server_hash;
  h.server_send(w);
  h.run_for(5 * kMs);
}

VisibilityClientConfig config_with_scene() {
  VisibilityClientConfig config = test_config();
  config.scene_hash = kClientSceneHash;
  return config;
}

TEST(ClientSession, AWelcomeForAnotherSceneFailsForGoodAndSaysBye) {
  Harness h(config_with_scene());
  answer_with_scene(h, 0x5555'6666'7777'8888ull);
  EXPECT_TRUE(h.client.failed());
  EXPECT_FALSE(h.client.connected());
  EXPECT_EQ(h.client.failure_kind(), ClientFailure::kSceneMismatch);
  EXPECT_FALSE(h.client.failed_authentication());
  EXPECT_NE(h.client.failure().find("5555666677778888"), std::string::npos) << h.client.failure();
  EXPECT_NE(h.client.failure().find("1111222233334444"), std::string::npos) << h.client.failure();
  // The server hears at once that the session it opened is over, and no pose follows.
  ASSERT_EQ(h.received<Bye>().size(), 1u);
  EXPECT_FALSE(h.client.send_pose(FramePose{1, 1, views_for(1)}));
  // Failed for good: no Hello again, even much later.
  const size_t hellos = h.received<Hello>().size();
  h.run_for(3000 * kMs);
  EXPECT_EQ(h.received<Hello>().size(), hellos);
}

TEST(ClientSession, AWelcomeForTheSameSceneConnects) {
  Harness h(config_with_scene());
  answer_with_scene(h, kClientSceneHash);
  EXPECT_TRUE(h.client.connected());
  EXPECT_EQ(h.client.failure_kind(), ClientFailure::kNone);
}

TEST(ClientSession, TimeoutRestartsWithANewNonce) {
  Harness h;
  h.connect();
  const uint64_t first_nonce = h.received<Hello>()[0].client_nonce;
  // The Welcome's default session timeout is 5 s; the scripted server stays silent.
  h.run_for(5'100 * kMs);
  EXPECT_FALSE(h.client.connected());
  const ClientNetStats s = h.client.stats();
  EXPECT_EQ(s.session_timeouts, 1u);
  EXPECT_EQ(s.sessions_restarted, 1u);
  const auto hellos = h.received<Hello>();
  ASSERT_GE(hellos.size(), 2u);
  EXPECT_NE(hellos.back().client_nonce, first_nonce);
  h.server_send(h.welcome_for(hellos.back().client_nonce));
  h.run_for(kMs);
  EXPECT_TRUE(h.client.connected());
  EXPECT_EQ(h.client.stats().sessions_started, 2u);
}

TEST(ClientSession, AClientThatHadASessionNeverGivesUpOnTheServer) {
  Harness h;  // keep_retrying off: only a client that never reached a server gives up
  h.connect();
  h.run_for(5'100 * kMs);  // the server went silent: the session times out
  EXPECT_FALSE(h.client.connected());
  h.run_for(30'000 * kMs);  // far past the 5 s give-up time
  EXPECT_FALSE(h.client.failed()) << h.client.failure();
  const ClientNetStats s = h.client.stats();
  EXPECT_GT(s.hellos_backed_off, 0u);
  const auto hellos = h.received<Hello>();
  h.server_send(h.welcome_for(hellos.back().client_nonce));  // the server is back
  h.run_for(kMs);
  EXPECT_TRUE(h.client.connected());
  EXPECT_EQ(h.client.stats().sessions_started, 2u);
}

TEST(ClientSession, ByeUnknownSessionRestartsAndAForeignByeDoesNot) {
  Harness h;
  h.connect();
  h.server_send(Bye{ByeReason::kUnknownSession}, kToken + 1);  // another session's token
  h.run_for(kMs);
  EXPECT_TRUE(h.client.connected());
  EXPECT_EQ(h.client.stats().datagrams_foreign, 1u);
  h.server_send(Bye{ByeReason::kUnknownSession}, kToken);
  h.run_for(2 * kMs);  // the Bye, then the new Hello
  EXPECT_FALSE(h.client.connected());
  EXPECT_FALSE(h.client.failed());
  EXPECT_EQ(h.client.stats().sessions_restarted, 1u);
  EXPECT_EQ(h.received<Hello>().size(), 2u);
}

TEST(ClientSession, HeartbeatsEveryIntervalAndTheyKeepTheSessionAlive) {
  Harness h;
  h.connect();
  for (int second = 0; second < 10; ++second) {
    h.run_for(1'000 * kMs);
    Heartbeat hb;
    hb.send_time_ns = h.clock.now_ns();
    h.server_send(hb);
  }
  h.run_for(kMs);
  EXPECT_TRUE(h.client.connected());
  const auto heartbeats = h.received<Heartbeat>();
  EXPECT_GE(heartbeats.size(), 10u);
  EXPECT_LE(heartbeats.size(), 11u);
  for (size_t i = 1; i < heartbeats.size(); ++i)
    EXPECT_EQ(heartbeats[i].send_time_ns - heartbeats[i - 1].send_time_ns, 1'000 * kMs);
  EXPECT_EQ(h.client.stats().heartbeats_received, 10u);
}

TEST(ClientSession, PosesOnlyWhenConnectedAndWithIncreasingFrameNumbers) {
  Harness h;
  h.client.tick();
  EXPECT_FALSE(h.client.send_pose(FramePose{1, 100, views_for(1)}));
  h.connect();
  EXPECT_TRUE(h.client.send_pose(FramePose{5, 100, views_for(5)}));
  EXPECT_FALSE(h.client.send_pose(FramePose{5, 100, views_for(5)}));
  EXPECT_FALSE(h.client.send_pose(FramePose{4, 100, views_for(4)}));
  EXPECT_FALSE(h.client.send_pose(FramePose{6, -1, views_for(6)}));
  EXPECT_FALSE(h.client.send_pose(FramePose{6, 200, views_for(6), -1}));  // negative scene time
  EXPECT_TRUE(h.client.send_pose(FramePose{6, 200, views_for(6), 150}));
  h.run_for(kMs);
  const auto poses = h.received<PoseUpdate>();
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].frame, 5u);
  EXPECT_EQ(poses[1].frame, 6u);
  EXPECT_EQ(poses[1].display_time_ns, 200);
  EXPECT_EQ(poses[0].scene_time_ns, 0);
  EXPECT_EQ(poses[1].scene_time_ns, 150);  // FramePose's scene time, as sent
  EXPECT_EQ(poses[1].views[1].pose.position, views_for(6)[1].pose.position);
  const ClientNetStats s = h.client.stats();
  EXPECT_EQ(s.poses_sent, 2u);
  EXPECT_EQ(s.poses_not_connected, 1u);
  EXPECT_EQ(s.poses_refused, 4u);
  // Datagram sequence numbers count up per datagram sent.
  std::set<uint32_t> sequences;
  for (const auto& r : h.from_client) sequences.insert(r.datagram.sequence);
  EXPECT_EQ(sequences.size(), h.from_client.size());
}

TEST(ClientSession, BadConfigThrows) {
  net::VirtualClock clock;
  net::SimulatedLink link({}, clock);
  VisibilityClientConfig c = test_config();
  c.format.display.width = 0;
  EXPECT_THROW(VisibilityClient(c, link, clock), std::invalid_argument);
  c = test_config();
  c.scene_id = std::string("room\n");
  EXPECT_THROW(VisibilityClient(c, link, clock), std::invalid_argument);
  c = test_config();
  c.max_frames_in_flight = 1;
  EXPECT_THROW(VisibilityClient(c, link, clock), std::invalid_argument);
}

}  // namespace
}  // namespace dhr::client::test
