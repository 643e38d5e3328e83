// Authentication end to end (docs/security.md): the real VisibilityService (Embree on the default room) and
// the real VisibilityClient, each behind a SimulatedLink on one VirtualClock, every datagram captured on the
// way. With the same key a session carries bit-exact frames and nothing travels unprotected; captured
// datagrams replayed, damaged, sealed under another key or sent plain are counted and dropped before any
// work (no trace, no session, no state change); a wrong key, a missing key and a server without a key end
// the client's handshake with one clear reason.
#include "loopback_rig.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <vector>

#include "net/simulated_link.hpp"
#include "secure/envelope.hpp"
#include "scene/scene_hash.hpp"

namespace dhr::integration {
namespace {

using Bytes = std::vector<uint8_t>;
constexpr int64_t kStepNs = net::kNsPerMs;

class SecurePair {
 public:
  SecurePair(std::optional<secure::Key> server_key, std::optional<secure::Key> client_key)
      : up_({}, clock_), down_({}, clock_) {
    server::ServiceConfig config;
    config.scene_id = "default_room";
    config.scene_hash = scene_content_hash(TracedScene::get().scene);
    config.token_seed = 7;
    config.key = std::move(server_key);
    service_ = std::make_unique<server::VisibilityService>(*TracedScene::get().tracer, config, down_, clock_);
    client::VisibilityClientConfig cc = client_config(size_);
    cc.key = std::move(client_key);
    cc.server = server_address_;
    client_ = std::make_unique<client::VisibilityClient>(cc, up_, clock_);
  }

  // Advances the clock step by step: ticks both sides, carries every datagram (captured), traces.
  void pump(int steps) {
    for (int i = 0; i < steps; ++i) {
      clock_.advance_ns(kStepNs);
      client_->tick();
      service_->tick();
      up_.deliver_due([&](const net::SimulatedDelivery& d) {
        up_log_.emplace_back(d.bytes.begin(), d.bytes.end());
        service_->on_datagram(d.bytes, client_address_);
      });
      service_->process_pending();
      down_.deliver_due([&](const net::SimulatedDelivery& d) {
        down_log_.emplace_back(d.bytes.begin(), d.bytes.end());
        client_->on_datagram(d.bytes);
      });
    }
  }
  void connect() {
    pump(5);
    ASSERT_TRUE(client_->connected()) << client_->failure();
  }
  // Sends poses of frames [first, first + n), pumping a few steps after each.
  void poses(uint64_t first, uint64_t n) {
    for (uint64_t f = first; f < first + n; ++f) {
      FramePose pose{f, static_cast<int64_t>(f) * 11'000'000, views_for_frame(f, size_)};
      EXPECT_TRUE(client_->send_pose(pose));
      traced_[f] = pose.views;
      pump(3);
    }
  }
  void inject_to_server(const Bytes& bytes) { service_->on_datagram(bytes, client_address_); }

  server::VisibilityService& service() { return *service_; }
  client::VisibilityClient& client() { return *client_; }
  const std::vector<Bytes>& up_log() const { return up_log_; }
  const std::vector<Bytes>& down_log() const { return down_log_; }
  const EyeSize& size() const { return size_; }
  const std::map<uint64_t, std::array<View, 2>>& traced() const { return traced_; }

 private:
  EyeSize size_;
  net::VirtualClock clock_{1'000'000'000};
  net::SimulatedLink up_;
  net::SimulatedLink down_;
  net::PeerAddress client_address_ = net::PeerAddress::ipv4({10, 0, 0, 7}, 5000);
  net::PeerAddress server_address_ = net::PeerAddress::ipv4({10, 0, 0, 1}, 4000);
  std::unique_ptr<server::VisibilityService> service_;
  std::unique_ptr<client::VisibilityClient> client_;
  std::vector<Bytes> up_log_;
  std::vector<Bytes> down_log_;
  std::map<uint64_t, std::array<View, 2>> traced_;
};

MessageType type_of(const Bytes& b) { return static_cast<MessageType>(b[5]); }

TEST(SecureSession, SameKeyCarriesBitExactFramesAndNothingTravelsInTheClear) {
  const secure::Key key = secure::Key::random();
  SecurePair pair(key, key);
  pair.connect();
  pair.poses(1, 8);
  pair.pump(20);
  const client::ClientNetStats c = pair.client().stats();
  const server::ServiceStats s = pair.service().stats();
  EXPECT_GE(c.frames_completed, 8u);
  EXPECT_EQ(c.auth_failed + c.replayed + c.unauthenticated + c.datagrams_rejected, 0u);
  EXPECT_EQ(s.auth_failed + s.replayed + s.unauthenticated + s.datagrams_rejected, 0u);
  // Every datagram either way is sealed, but the Hello and the Welcome, which carry the handshake tag.
  for (const auto* log : {&pair.up_log(), &pair.down_log()}) {
    for (const Bytes& b : *log) {
      const bool handshake = type_of(b) == MessageType::kHello || type_of(b) == MessageType::kWelcome;
      EXPECT_EQ(secure::datagram_flags(b), handshake ? secure::kFlagAuthenticated : secure::kFlagSealed)
          << to_string(type_of(b));
    }
  }
  // What the client takes is the tracer's output for the traced view, bit for bit.
  size_t checked = 0;
  for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
    VisibilityFrame frame;
    ASSERT_TRUE(pair.client().take_newest(eye, frame));
    ASSERT_TRUE(frame.complete);
    const View& traced = pair.traced().at(frame.frame_number)[static_cast<size_t>(eye)];
    EXPECT_TRUE(frame.buffer == reference_trace(traced, pair.size()));
    ++checked;
  }
  EXPECT_EQ(checked, 2u);
}

TEST(SecureSession, ReplayedDamagedForeignKeyAndPlainDatagramsAreDroppedBeforeAnyWork) {
  const secure::Key key = secure::Key::random();
  SecurePair pair(key, key);
  pair.connect();
  pair.poses(1, 4);
  pair.pump(20);
  const server::ServiceStats before = pair.service().stats();
  const client::ClientNetStats client_before = pair.client().stats();
  ASSERT_GE(before.frames_traced, 4u);

  // Replays: every sealed datagram the client sent, again (poses, heartbeats).
  size_t sealed_up = 0;
  std::optional<Bytes> pose;
  for (const Bytes& b : pair.up_log()) {
    if (secure::datagram_flags(b) != secure::kFlagSealed) continue;
    ++sealed_up;
    if (type_of(b) == MessageType::kPoseUpdate) pose = b;
    pair.inject_to_server(b);
  }
  ASSERT_TRUE(pose);
  // Damaged: each byte of a captured pose flipped in turn, but the version (another protocol: the decoder's),
  // the flags (then not sealed: unauthenticated) and the token (another, unknown session).
  size_t damaged = 0;
  for (size_t i = 0; i < pose->size(); ++i) {
    if (i == 4 || i == 6 || i == 7 || (i >= 8 && i < 16)) continue;
    Bytes bad = *pose;
    bad[i] ^= 0x40;
    pair.inject_to_server(bad);
    ++damaged;
  }
  // Sealed under another key: a well-formed pose of a newer frame.
  PoseUpdate forged;
  forged.frame = 1000;
  forged.display_time_ns = 1;
  forged.views = views_for_frame(1000, pair.size());
  const uint64_t token = pair.service().sessions().at(0).token;
  const Bytes plain = encode_datagram(Datagram{token, 5000, forged});
  Bytes other(plain.size() + secure::kSealTagSize);
  ASSERT_GT(secure::seal(secure::Key::random(), plain, other), 0u);
  pair.inject_to_server(other);
  // In the clear, with the session's token.
  pair.inject_to_server(plain);
  // A Hello with the handshake tag of another key: no session, a plain Bye(auth failed).
  Bytes hello = encode_datagram(Datagram{0, 0, Hello{}});
  hello.resize(hello.size() + secure::kHandshakeTrailerSize);
  ASSERT_GT(secure::HandshakeKey(secure::Key::random()).authenticate(hello, hello.size() - secure::kHandshakeTrailerSize,
                                                                    secure::random_bytes()),
            0u);
  pair.inject_to_server(hello);
  EXPECT_EQ(pair.service().process_pending(), 0u);  // nothing to trace

  const server::ServiceStats after = pair.service().stats();
  EXPECT_EQ(after.replayed - before.replayed, sealed_up);
  EXPECT_EQ(after.auth_failed - before.auth_failed, damaged + 2);  // + another key's seal and Hello tag
  EXPECT_EQ(after.unauthenticated - before.unauthenticated, 1u);
  EXPECT_EQ(after.frames_traced, before.frames_traced);
  EXPECT_EQ(after.poses_received, before.poses_received);
  EXPECT_EQ(after.sessions_opened, before.sessions_opened);
  EXPECT_EQ(after.hellos, before.hellos);

  // The client drops replayed server datagrams (shards, heartbeats) the same way.
  size_t sealed_down = 0;
  for (const Bytes& b : pair.down_log()) {
    if (secure::datagram_flags(b) != secure::kFlagSealed) continue;
    ++sealed_down;
    pair.client().on_datagram(b);
  }
  const client::ClientNetStats client_after = pair.client().stats();
  EXPECT_EQ(client_after.replayed - client_before.replayed, sealed_down);
  EXPECT_EQ(client_after.shards_received, client_before.shards_received);
  // And the session goes on.
  pair.poses(5, 2);
  pair.pump(20);
  EXPECT_GT(pair.service().stats().frames_traced, after.frames_traced);
  EXPECT_TRUE(pair.client().connected());
}

TEST(SecureSession, WrongKeyMissingKeyAndAServerWithoutKeyFailWithOneClearReason) {
  {
    SCOPED_TRACE("another key");
    SecurePair pair(secure::Key::random(), secure::Key::random());
    pair.pump(20);
    EXPECT_TRUE(pair.client().failed());
    EXPECT_TRUE(pair.client().failed_authentication());
    EXPECT_NE(pair.client().failure().find("rejected this client's key"), std::string::npos) << pair.client().failure();
    EXPECT_GE(pair.service().stats().auth_failed, 1u);
    EXPECT_EQ(pair.service().stats().sessions_opened, 0u);
  }
  {
    SCOPED_TRACE("no client key");
    SecurePair pair(secure::Key::random(), std::nullopt);
    pair.pump(20);
    EXPECT_TRUE(pair.client().failed_authentication());
    EXPECT_NE(pair.client().failure().find("requires authentication"), std::string::npos) << pair.client().failure();
    EXPECT_GE(pair.service().stats().unauthenticated, 1u);
    EXPECT_EQ(pair.service().stats().sessions_opened, 0u);
  }
  {
    SCOPED_TRACE("server without a key");
    SecurePair pair(std::nullopt, secure::Key::random());
    pair.pump(20);
    EXPECT_TRUE(pair.client().failed_authentication());
    EXPECT_NE(pair.client().failure().find("without authentication"), std::string::npos) << pair.client().failure();
  }
  {
    SCOPED_TRACE("neither has a key: the unauthenticated protocol");
    SecurePair pair(std::nullopt, std::nullopt);
    pair.connect();
    pair.poses(1, 2);
    pair.pump(10);
    EXPECT_GE(pair.client().stats().frames_completed, 2u);
  }
}

}  // namespace
}  // namespace dhr::integration
