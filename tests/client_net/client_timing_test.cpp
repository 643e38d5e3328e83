// VisibilityClient measurements on a virtual clock with known link delays: the response time of a frame
// (pose sent -> both eyes complete) and the clock offset from Heartbeat echoes are exact.
#include "client_harness.hpp"

namespace dhr::client::test {
namespace {

TEST(ClientTiming, ResponseTimeIsPoseSentToBothEyesComplete) {
  Harness h(test_config(), Harness::delay(10.0), Harness::delay(10.0));
  h.connect();
  const int64_t sent = h.clock.now_ns();
  ASSERT_TRUE(h.client.send_pose(FramePose{1, 0, views_for(1)}));
  while (h.received<PoseUpdate>().empty()) h.run_for(kMs);
  EXPECT_EQ(h.from_client.back().receive_ns, sent + 10 * kMs);
  h.run_for(5 * kMs);  // the "trace"
  h.send_frame(1, Eye::kLeft);
  h.run_for(4 * kMs);
  h.send_frame(1, Eye::kRight);  // the right eye leaves 4 ms later
  h.run_for(30 * kMs);
  EXPECT_EQ(h.client.response_ns(1), 29 * kMs);  // 10 up + 5 trace + 4 left eye + 10 down
  EXPECT_FALSE(h.client.response_ns(2).has_value());
  const ClientNetStats s = h.client.stats();
  EXPECT_EQ(s.response.count, 1u);
  EXPECT_EQ(s.response.last_ns, 29 * kMs);
  VisibilityFrame v;
  ASSERT_TRUE(h.client.take_newest(Eye::kLeft, v));
  EXPECT_EQ(v.received_ns, sent + 25 * kMs);  // usable from when the left eye completed
}

TEST(ClientTiming, IncompleteFramesHaveNoResponseTime) {
  Harness h(test_config(), Harness::delay(10.0), Harness::delay(10.0));
  h.connect();
  ASSERT_TRUE(h.client.send_pose(FramePose{1, 0, views_for(1)}));
  h.run_for(15 * kMs);
  h.send_frame(1, Eye::kLeft);
  const auto right = shards_for(1, Eye::kRight);
  for (size_t i = 1; i < right.size(); ++i) h.send_shard(right[i]);
  h.run_for(50 * kMs);
  EXPECT_FALSE(h.client.response_ns(1).has_value());
  EXPECT_EQ(h.client.stats().response.count, 0u);
}

// The scripted server answers the client's first Heartbeat after `hold`, on a clock `offset` ahead.
void run_heartbeat_exchange(Harness& h, int64_t offset, int64_t hold) {
  h.connect();
  while (h.received<Heartbeat>().empty()) h.run_for(kMs);
  const Heartbeat from_client = h.received<Heartbeat>().front();
  h.run_for(hold);
  Heartbeat reply;
  reply.send_time_ns = h.clock.now_ns() + offset;
  reply.echo_time_ns = from_client.send_time_ns;
  reply.echo_delay_ns = hold;
  h.server_send(reply);
  h.run_for(100 * kMs);
}

TEST(ClientTiming, ClockOffsetFromHeartbeatEchoIsExactForASymmetricDelay) {
  Harness h(test_config(), Harness::delay(10.0), Harness::delay(10.0));
  const int64_t offset = 123'456'789;
  run_heartbeat_exchange(h, offset, 3 * kMs);
  const ClientNetStats s = h.client.stats();
  ASSERT_TRUE(s.clock_offset_valid);
  EXPECT_EQ(s.clock_offset_ns, offset);
  EXPECT_EQ(s.clock_rtt_ns, 20 * kMs);  // the server's hold time excluded
  EXPECT_EQ(s.clock_uncertainty_ns, 10 * kMs);
  EXPECT_EQ(s.clock_samples, 1u);
}

TEST(ClientTiming, AsymmetricDelayBiasesTheOffsetByHalfTheDifference) {
  Harness h(test_config(), Harness::delay(10.0), Harness::delay(30.0));
  const int64_t offset = -700 * kMs;  // server times stay >= 0 (the clock starts at 1 s)
  run_heartbeat_exchange(h, offset, 1 * kMs);
  const ClientNetStats s = h.client.stats();
  ASSERT_TRUE(s.clock_offset_valid);
  EXPECT_EQ(s.clock_offset_ns, offset + (10 - 30) * kMs / 2);
  EXPECT_EQ(s.clock_rtt_ns, 40 * kMs);
  EXPECT_LE(std::abs(s.clock_offset_ns - offset), s.clock_uncertainty_ns);
}

}  // namespace
}  // namespace dhr::client::test
