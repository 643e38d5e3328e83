#include "net/clock.hpp"
#include "net/simulated_link.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <vector>

namespace dhr::net {
namespace {

std::vector<uint8_t> payload_for(uint32_t index) {
  std::vector<uint8_t> bytes(4 + index % 7, 0xab);
  std::memcpy(bytes.data(), &index, sizeof(index));
  return bytes;
}

uint32_t index_of(std::span<const uint8_t> bytes) {
  uint32_t index = 0;
  std::memcpy(&index, bytes.data(), sizeof(index));
  return index;
}

TEST(SimulatedLink, PerfectLinkDeliversImmediatelyInOrder) {
  VirtualClock clock(1000);
  SimulatedLink link(ImpairmentParams{}, clock);
  for (uint32_t i = 0; i < 10; ++i) ASSERT_TRUE(link.send(payload_for(i)));
  std::vector<uint32_t> received;
  EXPECT_EQ(link.deliver_due([&](const SimulatedDelivery& d) {
              EXPECT_EQ(d.delivery_time_ns, 1000);
              received.push_back(index_of(d.bytes));
            }),
            10u);
  EXPECT_EQ(received, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(link.in_flight(), 0u);
  EXPECT_FALSE(link.next_delivery_ns().has_value());
}

TEST(SimulatedLink, NothingArrivesBeforeItsTime) {
  VirtualClock clock(0);
  ImpairmentParams params;
  params.delay_ms = 10.0;
  SimulatedLink link(params, clock);
  const PeerAddress to = PeerAddress::loopback_ipv4(5000);
  ASSERT_TRUE(link.send_to(payload_for(1), to));
  ASSERT_EQ(link.next_delivery_ns(), 10 * kNsPerMs);
  int delivered = 0;
  const DeliverySink sink = [&](const SimulatedDelivery& d) {
    EXPECT_EQ(d.to, to);
    EXPECT_EQ(d.send_time_ns, 0);
    ++delivered;
  };
  clock.set_ns(10 * kNsPerMs - 1);
  EXPECT_EQ(link.deliver_due(sink), 0u);
  clock.set_ns(10 * kNsPerMs);
  EXPECT_EQ(link.deliver_due(sink), 1u);
  EXPECT_EQ(delivered, 1);
}

TEST(SimulatedLink, BadNetworkDeliversEverythingScheduledInTimeOrder) {
  VirtualClock clock(0);
  ImpairmentParams params;
  params.delay_ms = 50.0;
  params.jitter_ms = 20.0;
  params.loss = 0.3;
  params.reorder = 0.05;
  params.duplicate = 0.05;
  params.seed = 2024;
  SimulatedLink link(params, clock);

  constexpr uint32_t kCount = 5000;
  constexpr int64_t kStep = kNsPerMs / 2;
  std::map<uint32_t, int> expected_copies;  // from the decisions the link reports
  std::map<uint32_t, int> copies;
  int64_t previous_delivery = 0;
  uint64_t out_of_order = 0;
  uint32_t highest_index = 0;
  const DeliverySink sink = [&](const SimulatedDelivery& d) {
    EXPECT_LE(d.delivery_time_ns, clock.now_ns());
    EXPECT_GT(d.delivery_time_ns, clock.now_ns() - kStep);  // released at the first chance, not later
    EXPECT_GE(d.delivery_time_ns, previous_delivery);       // time order
    EXPECT_GE(d.delivery_time_ns, d.send_time_ns);
    previous_delivery = d.delivery_time_ns;
    const uint32_t index = index_of(d.bytes);
    EXPECT_EQ(d.bytes.size(), payload_for(index).size());
    EXPECT_EQ(d.sequence, index);
    ++copies[index];
    if (index < highest_index) ++out_of_order;
    highest_index = std::max(highest_index, index);
  };
  for (uint32_t i = 0; i < kCount; ++i) {
    ImpairmentDecision decision;
    ASSERT_TRUE(link.send_at(payload_for(i), PeerAddress(), clock.now_ns(), &decision));
    if (decision.delivery_count > 0) expected_copies[i] = decision.delivery_count;
    clock.advance_ns(kStep);
    link.deliver_due(sink);
  }
  while (link.next_delivery_ns().has_value()) {
    clock.advance_ns(kStep);
    link.deliver_due(sink);
  }
  const SimulatedLinkStats stats = link.stats();
  EXPECT_EQ(copies, expected_copies);
  EXPECT_EQ(stats.model.sent, kCount);
  EXPECT_EQ(stats.delivered, stats.model.deliveries);
  EXPECT_EQ(stats.delivered, stats.model.sent - stats.model.lost + stats.model.duplicated);
  EXPECT_EQ(stats.in_flight, 0u);
  EXPECT_GT(stats.model.lost, 0u);
  EXPECT_GT(stats.model.duplicated, 0u);
  EXPECT_GT(stats.model.reordered, 0u);
  EXPECT_GT(out_of_order, 0u);  // reordering is visible to the receiver
}

TEST(SimulatedLink, SameSeedSameDeliveries) {
  const auto trace = [] {
    VirtualClock clock(0);
    ImpairmentParams params;
    params.jitter_ms = 5.0;
    params.loss = 0.2;
    params.reorder = 0.1;
    params.duplicate = 0.1;
    params.seed = 3;
    SimulatedLink link(params, clock);
    std::vector<std::pair<uint32_t, int64_t>> out;
    for (uint32_t i = 0; i < 500; ++i) {
      link.send(payload_for(i));
      clock.advance_ns(kNsPerMs);
      link.deliver_due([&](const SimulatedDelivery& d) { out.emplace_back(index_of(d.bytes), d.delivery_time_ns); });
    }
    link.deliver_until(INT64_MAX, [&](const SimulatedDelivery& d) { out.emplace_back(index_of(d.bytes), d.delivery_time_ns); });
    return out;
  };
  EXPECT_EQ(trace(), trace());
}

TEST(SimulatedLink, MemoryIsBoundedAndEmptyDatagramsRefused) {
  VirtualClock clock(0);
  ImpairmentParams params;
  params.delay_ms = 1000.0;
  SimulatedLink link(params, clock, 10);
  size_t accepted = 0;
  for (uint32_t i = 0; i < 100; ++i) accepted += link.send(payload_for(i)) ? 1 : 0;
  EXPECT_LE(link.in_flight(), 10u);
  EXPECT_EQ(accepted, link.in_flight());
  const SimulatedLinkStats stats = link.stats();
  EXPECT_EQ(stats.dropped_overflow, 100 - accepted);
  EXPECT_EQ(stats.model.sent, accepted);  // refused datagrams do not advance the schedule
  EXPECT_FALSE(link.send({}));
  EXPECT_EQ(link.stats().rejected, 1u);
}

TEST(SimulatedLink, InvalidParamsThrow) {
  VirtualClock clock;
  ImpairmentParams params;
  params.duplicate = 3;
  EXPECT_THROW(SimulatedLink(params, clock), std::invalid_argument);
}

TEST(SimulatedLink, SinkMaySendIntoTheLink) {
  // A reflector: whatever arrives is sent back through the same link (tests the lock is not held).
  VirtualClock clock(0);
  ImpairmentParams params;
  params.delay_ms = 1.0;
  SimulatedLink link(params, clock);
  link.send(payload_for(0));
  int hops = 0;
  for (int step = 0; step < 10; ++step) {
    clock.advance_ns(kNsPerMs);
    link.deliver_due([&](const SimulatedDelivery& d) {
      ++hops;
      link.send(d.bytes);
    });
  }
  EXPECT_EQ(hops, 10);
}

}  // namespace
}  // namespace dhr::net
