// Test harness for VisibilityClient: the real client on two SimulatedLinks (uplink, downlink) driven by a
// VirtualClock, and a scripted server peer that decodes what the client sends and answers with real
// encoded datagrams (Welcome, shards from the real codec, Heartbeat, Bye). Nothing of the client is mocked.
#pragma once
#include "codec/codec.hpp"
#include "protocol/protocol.hpp"
#include "metrics/visibility_synthetic.hpp"
#include "net/clock.hpp"
#include "net/simulated_link.hpp"
#include "link/visibility_client.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <variant>
#include <vector>

namespace dhr::client::test {

inline constexpr int64_t kMs = net::kNsPerMs;
inline constexpr uint16_t kEyeW = 60, kEyeH = 40, kGuard = 2;
inline constexpr uint32_t kBufW = kEyeW + 2 * kGuard, kBufH = kEyeH + 2 * kGuard;
inline constexpr uint8_t kLights = 16;  // 16-bit masks: random buffers need several shards
inline constexpr uint64_t kToken = 0x1234'5678'9ABC'DEF0ull;

inline VisibilityClientConfig test_config() {
  VisibilityClientConfig c;
  c.format = TracedFormat{Extent{kEyeW, kEyeH}, GuardBand{kGuard, kGuard}};
  c.light_count_wanted = kLights;
  c.nonce_seed = 7;
  return c;
}

inline View view_for(uint64_t frame, Eye eye) {
  View v;
  v.pose.position = {0.01 * static_cast<double>(frame) + (eye == Eye::kRight ? 0.064 : 0.0), 1.6, 0.0};
  return v;
}

inline std::array<View, 2> views_for(uint64_t frame) { return {view_for(frame, Eye::kLeft), view_for(frame, Eye::kRight)}; }

// Distinct content per (frame, eye).
inline VisibilityBuffer buffer_for(uint64_t frame, Eye eye) {
  return make_random_visibility(kBufW, kBufH, kLights, frame * 2 + static_cast<uint64_t>(eye) + 1);
}

// The scene time the server traced `frame` for (every shard of the frame names it).
inline int64_t scene_time_for(uint64_t frame) { return static_cast<int64_t>(frame) * 11'000'000 + 5'000'000; }

inline std::vector<VisibilityShard> shards_for(uint64_t frame, Eye eye) {
  std::vector<VisibilityShard> shards =
      make_visibility_shards(buffer_for(frame, eye), frame, eye, view_for(frame, eye));
  for (VisibilityShard& s : shards) s.scene_time_ns = scene_time_for(frame);
  return shards;
}

class Harness {
 public:
  explicit Harness(const VisibilityClientConfig& config = test_config(), const net::ImpairmentParams& up = {},
                   const net::ImpairmentParams& down = {})
      : clock(kStart), uplink(up, clock), downlink(down, clock), client(config, uplink, clock) {}

  static constexpr int64_t kStart = 1'000 * kMs;

  // Advances the virtual clock in 1 ms steps to `until`, delivering both links and ticking the client.
  void run_until(int64_t until) {
    while (clock.now_ns() < until) {
      clock.advance_ns(kMs);
      deliver();
      client.tick();
    }
  }
  void run_for(int64_t duration) { run_until(clock.now_ns() + duration); }
  // Delivers what is due now without advancing the clock or ticking.
  void deliver() {
    uplink.deliver_due([this](const net::SimulatedDelivery& d) {
      Datagram datagram;
      ASSERT_EQ(decode_datagram(d.bytes, datagram), DecodeError::kNone) << "the client sent an invalid datagram";
      from_client.push_back({datagram, d.delivery_time_ns});
    });
    downlink.deliver_due([this](const net::SimulatedDelivery& d) { client.on_datagram(d.bytes, d.delivery_time_ns); });
  }

  // The scripted server: sends on the downlink now.
  void server_send(const Message& message, uint64_t token = kToken) {
    const std::vector<uint8_t> bytes = encode_datagram(Datagram{token, server_sequence++, message});
    ASSERT_FALSE(bytes.empty());
    downlink.send(bytes);
  }
  void server_send_raw(std::span<const uint8_t> bytes) { downlink.send(bytes); }
  void send_shard(const VisibilityShard& shard, uint64_t token = kToken) { server_send(shard, token); }
  void send_frame(uint64_t frame, Eye eye) {
    for (const VisibilityShard& s : shards_for(frame, eye)) send_shard(s);
  }

  Welcome welcome_for(uint64_t nonce) const {
    Welcome w;
    w.client_nonce = nonce;
    w.light_count = kLights;
    w.mask_bits = mask_width_for_light_count(kLights);
    w.buffer_width = kBufW;
    w.buffer_height = kBufH;
    w.guard_x = kGuard;
    w.guard_y = kGuard;
    return w;
  }

  // Client datagrams of one type received by the server so far.
  template <class T>
  std::vector<T> received() const {
    std::vector<T> out;
    for (const auto& r : from_client)
      if (const T* m = std::get_if<T>(&r.datagram.message)) out.push_back(*m);
    return out;
  }

  // Ticks until the first Hello arrives, answers it with a Welcome and runs until the client is connected.
  void connect() {
    client.tick();
    for (int i = 0; i < 1000 && received<Hello>().empty(); ++i) run_for(kMs);
    const auto hellos = received<Hello>();
    ASSERT_FALSE(hellos.empty());
    server_send(welcome_for(hellos.back().client_nonce));
    for (int i = 0; i < 1000 && !client.connected(); ++i) run_for(kMs);
    ASSERT_TRUE(client.connected());
  }

  static net::ImpairmentParams delay(double ms) {
    net::ImpairmentParams p;
    p.delay_ms = ms;
    return p;
  }

  struct FromClient {
    Datagram datagram;
    int64_t receive_ns = 0;
  };

  net::VirtualClock clock;
  net::SimulatedLink uplink;    // client -> server
  net::SimulatedLink downlink;  // server -> client
  VisibilityClient client;
  std::vector<FromClient> from_client;
  uint32_t server_sequence = 0;
};

}  // namespace dhr::client::test
