// UdpVisibilityClient on a real socket against a hand-driven peer (a plain UdpSocket on 127.0.0.1): Hellos
// go out well-formed and retried with one nonce until the client gives up; datagrams from anyone but the
// server never reach the protocol layer; a Welcome from the server connects.
#include "loopback_rig.hpp"
#include "net/udp_socket.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <thread>
#include <variant>
#include <vector>

namespace dhr::integration {
namespace {

// A bare UDP peer that records every datagram it receives (decoded) with the sender's address.
struct RawPeer {
  net::UdpSocket socket;
  std::mutex mutex;
  std::vector<std::pair<Datagram, net::PeerAddress>> received;
  size_t undecodable = 0;

  RawPeer() {
    socket.open(net::UdpSocketConfig{}, [this](const net::ReceivedDatagram& d) {
      Datagram datagram;
      const std::lock_guard lock(mutex);
      if (decode_datagram(d.bytes, datagram) == DecodeError::kNone) {
        received.emplace_back(datagram, d.from);
      } else {
        ++undecodable;
      }
    });
  }
  std::vector<Hello> hellos() {
    const std::lock_guard lock(mutex);
    std::vector<Hello> out;
    for (const auto& [d, from] : received)
      if (const auto* h = std::get_if<Hello>(&d.message)) out.push_back(*h);
    return out;
  }
  net::PeerAddress last_sender() {
    const std::lock_guard lock(mutex);
    return received.empty() ? net::PeerAddress() : received.back().second;
  }
};

template <class Predicate>
bool tick_until(client::UdpVisibilityClient& client, Predicate predicate) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!predicate()) {
    if (std::chrono::steady_clock::now() > deadline) return predicate();
    client.client().tick();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

TEST(UdpClient, RetriesHelloOverUdpThenGivesUp) {
  RawPeer server;
  client::VisibilityClientConfig config = client_config(EyeSize{});
  config.hello_retry_ns = 100 * net::kNsPerMs;
  config.hello_give_up_ns = 450 * net::kNsPerMs;
  client::UdpVisibilityClient client;
  client.connect(config, "127.0.0.1", server.socket.local_port());
  ASSERT_TRUE(tick_until(client, [&] { return client.client().failed(); }));
  EXPECT_NE(client.client().failure().find("no Welcome"), std::string::npos) << client.client().failure();
  const client::ClientNetStats s = client.client().stats();
  // Loopback delivers every Hello.
  ASSERT_TRUE(tick_until(client, [&] { return server.hellos().size() >= s.hellos_sent; }));
  const std::vector<Hello> hellos = server.hellos();
  EXPECT_EQ(hellos.size(), s.hellos_sent);
  EXPECT_GE(hellos.size(), 2u);  // 5 when the loop is never delayed (0, 100, ..., 400 ms); no timing asserted
  for (const Hello& h : hellos) {
    EXPECT_EQ(h.client_nonce, hellos[0].client_nonce);
    EXPECT_EQ(h.eye_width, config.format.display.width);
    EXPECT_EQ(h.scene_id, config.scene_id);
  }
  EXPECT_EQ(server.undecodable, 0u);
}

TEST(UdpClient, OnlyTheServerReachesTheProtocolAndItsWelcomeConnects) {
  RawPeer server;
  client::UdpVisibilityClient client;
  client.connect(client_config(EyeSize{}), "127.0.0.1", server.socket.local_port());
  ASSERT_TRUE(tick_until(client, [&] { return !server.hellos().empty(); }));
  const Hello hello = server.hellos().front();
  const net::PeerAddress client_address = server.last_sender();
  ASSERT_EQ(client_address.port(), client.local_port());

  Welcome welcome;
  welcome.client_nonce = hello.client_nonce;
  welcome.light_count = 3;
  welcome.mask_bits = mask_width_for_light_count(3);
  welcome.buffer_width = static_cast<uint16_t>(hello.eye_width + 2 * hello.guard_x);
  welcome.buffer_height = static_cast<uint16_t>(hello.eye_height + 2 * hello.guard_y);
  welcome.guard_x = hello.guard_x;
  welcome.guard_y = hello.guard_y;
  const std::vector<uint8_t> bytes = encode_datagram(Datagram{77, 0, welcome});

  // The right Welcome from another address: dropped by the endpoint, never seen by the protocol layer.
  RawPeer stranger;
  ASSERT_TRUE(stranger.socket.send_to(bytes, client_address));
  ASSERT_TRUE(tick_until(client, [&] { return client.udp_counters().dropped_foreign == 1; }));
  EXPECT_FALSE(client.client().connected());
  EXPECT_EQ(client.client().stats().datagrams_received, 0u);

  ASSERT_TRUE(server.socket.send_to(bytes, client_address));
  ASSERT_TRUE(tick_until(client, [&] { return client.client().connected(); }));
  EXPECT_EQ(client.client().welcome(), welcome);
  // The first Heartbeat follows with the new token.
  ASSERT_TRUE(tick_until(client, [&] {
    const std::lock_guard lock(server.mutex);
    for (const auto& [d, from] : server.received)
      if (std::holds_alternative<Heartbeat>(d.message) && d.session_token == 77) return true;
    return false;
  }));
  // close() says Bye with the token, and it leaves the socket before the socket stops.
  client.close();
  EXPECT_TRUE(tick_until(client, [&] {
    const std::lock_guard lock(server.mutex);
    for (const auto& [d, from] : server.received)
      if (std::holds_alternative<Bye>(d.message) && d.session_token == 77) return true;
    return false;
  }));
}

}  // namespace
}  // namespace dhr::integration
