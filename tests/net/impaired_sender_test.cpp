// ImpairedSender in front of a real UDP socket on loopback. The schedule is deterministic, so what
// arrives is checked against an ImpairmentModel replaying the same seed; timing is never asserted.
#include "net/clock.hpp"
#include "net/impaired_sender.hpp"
#include "net/udp_socket.hpp"
#include "wait_until.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace dhr::net {
namespace {

using test::wait_until;

struct CountingReceiver {
  UdpSocket socket;
  std::mutex mutex;
  std::map<uint32_t, int> copies;  // datagram index -> copies received
  size_t total = 0;

  CountingReceiver() {
    socket.open(UdpSocketConfig{}, [this](const ReceivedDatagram& d) {
      uint32_t index = 0;
      std::memcpy(&index, d.bytes.data(), sizeof(index));
      const std::lock_guard lock(mutex);
      ++copies[index];
      ++total;
    });
  }
  size_t received() {
    const std::lock_guard lock(mutex);
    return total;
  }
};

std::vector<uint8_t> datagram(uint32_t index) {
  std::vector<uint8_t> bytes(64, 0);
  std::memcpy(bytes.data(), &index, sizeof(index));
  return bytes;
}

TEST(ImpairedSender, DeliversExactlyWhatTheModelDecided) {
  CountingReceiver receiver;
  UdpSocket sender_socket;
  sender_socket.open(UdpSocketConfig{}, [](const ReceivedDatagram&) {});
  ImpairmentParams params;
  params.delay_ms = 5.0;
  params.jitter_ms = 3.0;
  params.loss = 0.3;
  params.reorder = 0.1;
  params.reorder_delay_ms = 4.0;
  params.duplicate = 0.2;
  params.seed = 17;
  constexpr uint32_t kCount = 300;

  ImpairedSender sender(sender_socket, params);
  for (uint32_t i = 0; i < kCount; ++i) ASSERT_TRUE(sender.send_to(datagram(i), receiver.socket.local_address()));
  ASSERT_TRUE(sender.wait_idle(30 * kNsPerSecond));

  // Loss and duplication do not depend on send times, so a replay gives the same decisions.
  ImpairmentModel replay(params);
  std::map<uint32_t, int> expected;
  for (uint32_t i = 0; i < kCount; ++i) {
    const ImpairmentDecision d = replay.next(0);
    if (d.delivery_count > 0) expected[i] = d.delivery_count;
  }
  const ImpairedSenderStats stats = sender.stats();
  EXPECT_EQ(stats.model, replay.stats());
  EXPECT_EQ(stats.forwarded, stats.model.deliveries);
  EXPECT_EQ(stats.forward_refused, 0u);
  EXPECT_EQ(stats.in_flight, 0u);
  ASSERT_TRUE(wait_until([&] { return receiver.received() == stats.model.deliveries; }));
  const std::lock_guard lock(receiver.mutex);
  EXPECT_EQ(receiver.copies, expected);
}

TEST(ImpairedSender, TotalLossDeliversNothing) {
  CountingReceiver receiver;
  UdpSocket sender_socket;
  sender_socket.open(UdpSocketConfig{}, [](const ReceivedDatagram&) {});
  ImpairmentParams params;
  params.loss = 1.0;
  {
    ImpairedSender sender(sender_socket, params);
    for (uint32_t i = 0; i < 50; ++i) EXPECT_TRUE(sender.send_to(datagram(i), receiver.socket.local_address()));
    ASSERT_TRUE(sender.wait_idle(10 * kNsPerSecond));
    EXPECT_EQ(sender.stats().model.lost, 50u);
    EXPECT_EQ(sender.stats().forwarded, 0u);
  }
  // A marker sent directly arrives; nothing before it did.
  ASSERT_TRUE(sender_socket.send_to(datagram(999), receiver.socket.local_address()));
  ASSERT_TRUE(wait_until([&] { return receiver.received() == 1; }));
  // The send completes on the I/O thread, possibly after the receiver already has the datagram.
  ASSERT_TRUE(wait_until([&] { return sender_socket.counters().datagrams_sent == 1; }));
  const std::lock_guard lock(receiver.mutex);
  EXPECT_EQ(receiver.copies.count(999), 1u);
}

TEST(ImpairedSender, InactiveParamsPassStraightThrough) {
  CountingReceiver receiver;
  UdpSocket sender_socket;
  sender_socket.open(UdpSocketConfig{}, [](const ReceivedDatagram&) {});
  ImpairedSender sender(sender_socket, ImpairmentParams{});
  for (uint32_t i = 0; i < 20; ++i) ASSERT_TRUE(sender.send_to(datagram(i), receiver.socket.local_address()));
  EXPECT_TRUE(sender.wait_idle(0));
  EXPECT_EQ(sender.stats().forwarded, 20u);
  EXPECT_EQ(sender.stats().model.sent, 20u);
  ASSERT_TRUE(wait_until([&] { return receiver.received() == 20; }));
  EXPECT_FALSE(sender.send_to({}, receiver.socket.local_address()));
  EXPECT_EQ(sender.stats().rejected, 1u);
}

TEST(ImpairedSender, InnerRefusalsAreCounted) {
  UdpSocket closed_socket;  // never opened: refuses every send
  ImpairmentParams params;
  params.delay_ms = 1.0;
  ImpairedSender sender(closed_socket, params);
  for (uint32_t i = 0; i < 5; ++i) ASSERT_TRUE(sender.send_to(datagram(i), PeerAddress::loopback_ipv4(9)));
  ASSERT_TRUE(sender.wait_idle(10 * kNsPerSecond));
  EXPECT_EQ(sender.stats().forward_refused, 5u);
  EXPECT_EQ(sender.stats().forwarded, 0u);
}

TEST(ImpairedSender, HeldDatagramsAreBoundedAndDiscardedOnDestruction) {
  UdpSocket sender_socket;
  sender_socket.open(UdpSocketConfig{}, [](const ReceivedDatagram&) {});
  ImpairmentParams params;
  params.delay_ms = 60'000.0;  // a minute: still held when the sender is destroyed
  auto sender = std::make_unique<ImpairedSender>(sender_socket, params, 8);
  size_t accepted = 0;
  for (uint32_t i = 0; i < 20; ++i) accepted += sender->send_to(datagram(i), PeerAddress::loopback_ipv4(9)) ? 1 : 0;
  EXPECT_LE(accepted, 8u);
  EXPECT_EQ(sender->stats().dropped_overflow, 20 - accepted);
  EXPECT_EQ(sender->stats().in_flight, accepted);
  EXPECT_FALSE(sender->wait_idle(0));
  sender.reset();  // must not wait a minute
  EXPECT_EQ(sender_socket.counters().datagrams_sent, 0u);
}

TEST(ImpairedSender, InvalidParamsThrow) {
  UdpSocket socket;
  ImpairmentParams params;
  params.jitter_ms = -1;
  EXPECT_THROW(ImpairedSender(socket, params), std::invalid_argument);
}

}  // namespace
}  // namespace dhr::net
