#include "net/clock.hpp"
#include "net/clock_sync.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <limits>

namespace dhr::net {
namespace {

constexpr int64_t kTrueOffset = 1'234'567'890'123;  // server clock - client clock

// One exchange on synthetic clocks: client sends at client time t0, the request takes `up` ns, the
// server holds it `hold` ns, the reply takes `down` ns.
ClockSample exchange(int64_t t0, int64_t up, int64_t hold, int64_t down, int64_t offset = kTrueOffset) {
  ClockSample s;
  s.t0_ns = t0;
  s.t1_ns = t0 + up + offset;
  s.t2_ns = s.t1_ns + hold;
  s.t3_ns = t0 + up + hold + down;
  return s;
}

TEST(ClockSync, SymmetricDelaysGiveTheExactOffset) {
  const auto estimate = offset_from_sample(exchange(5'000'000, 2'000'000, 700'000, 2'000'000));
  ASSERT_TRUE(estimate.has_value());
  EXPECT_EQ(estimate->offset_ns, kTrueOffset);
  EXPECT_EQ(estimate->rtt_ns, 4'000'000);  // the server's hold time is not part of the rtt
}

TEST(ClockSync, AsymmetryErrorIsHalfTheDifferenceAndWithinHalfTheRtt) {
  const int64_t up = 1'000'000;
  const int64_t down = 9'000'000;
  const auto estimate = offset_from_sample(exchange(0, up, 300'000, down));
  ASSERT_TRUE(estimate.has_value());
  EXPECT_EQ(estimate->offset_ns - kTrueOffset, (up - down) / 2);
  EXPECT_LE(std::llabs(estimate->offset_ns - kTrueOffset), estimate->rtt_ns / 2);
}

TEST(ClockSync, NegativeOffsetsWork) {
  const auto estimate = offset_from_sample(exchange(10'000, 500, 100, 500, -77'777'777));
  ASSERT_TRUE(estimate.has_value());
  EXPECT_EQ(estimate->offset_ns, -77'777'777);
}

TEST(ClockSync, ImpossibleSamplesAreRejected) {
  ClockSample backwards = exchange(1000, 10, 10, 10);
  backwards.t3_ns = backwards.t0_ns - 1;  // reply before request
  EXPECT_FALSE(offset_from_sample(backwards).has_value());
  ClockSample negative_hold = exchange(1000, 10, 10, 10);
  negative_hold.t2_ns = negative_hold.t1_ns - 1;
  EXPECT_FALSE(offset_from_sample(negative_hold).has_value());
  ClockSample hold_longer_than_round_trip = exchange(1000, 10, 10, 10);
  hold_longer_than_round_trip.t2_ns += 1000;
  EXPECT_FALSE(offset_from_sample(hold_longer_than_round_trip).has_value());
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  constexpr int64_t kMin = std::numeric_limits<int64_t>::min();
  EXPECT_FALSE(offset_from_sample(ClockSample{kMin, kMax, kMax, kMax}).has_value());
  EXPECT_FALSE(offset_from_sample(ClockSample{0, kMin, kMax, 1}).has_value());

  ClockOffsetEstimator estimator;
  EXPECT_FALSE(estimator.add_sample(backwards));
  EXPECT_FALSE(estimator.add_echo(0, -5, 100, 200));  // negative hold time
  EXPECT_EQ(estimator.rejected_count(), 2u);
  EXPECT_FALSE(estimator.has_estimate());
  EXPECT_EQ(estimator.offset_ns(), 0);
}

TEST(ClockSync, EstimatorRecoversOffsetUnderQueueingWithinTheAsymmetryBound) {
  // Base one-way delays 2 ms up / 3 ms down, plus queueing of up to 20 ms on either leg (a fixed
  // pseudo-random sequence). The min-rtt sample has the least queueing, so the estimate lands within
  // half the base asymmetry plus half the smallest queueing seen.
  ClockOffsetEstimator estimator(32);
  uint64_t state = 12345;
  auto next_queueing = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<int64_t>((state >> 33) % 20'000'000);
  };
  int64_t t0 = 1'000'000'000;
  int64_t min_extra = std::numeric_limits<int64_t>::max();
  for (int i = 0; i < 32; ++i) {
    const int64_t queue_up = i == 17 ? 0 : next_queueing();
    const int64_t queue_down = i == 17 ? 0 : next_queueing();
    min_extra = std::min(min_extra, queue_up + queue_down);
    ASSERT_TRUE(estimator.add_sample(exchange(t0, 2'000'000 + queue_up, 400'000, 3'000'000 + queue_down)));
    t0 += 100'000'000;
  }
  ASSERT_TRUE(estimator.has_estimate());
  EXPECT_EQ(min_extra, 0);
  EXPECT_EQ(estimator.rtt_ns(), 5'000'000);
  EXPECT_EQ(estimator.offset_ns(), kTrueOffset - 500'000);  // (2 ms - 3 ms) / 2
  EXPECT_LE(std::llabs(estimator.offset_ns() - kTrueOffset), estimator.uncertainty_ns());
  EXPECT_EQ(estimator.accepted_count(), 32u);
  EXPECT_EQ(estimator.samples_in_window(), 32u);
}

TEST(ClockSync, WindowForgetsOldSamples) {
  ClockOffsetEstimator estimator(4);
  ASSERT_TRUE(estimator.add_sample(exchange(0, 100, 0, 100, 5000)));  // best rtt, offset 5000
  for (int i = 1; i <= 3; ++i) {
    ASSERT_TRUE(estimator.add_sample(exchange(i * 1'000'000, 1000, 0, 1000, 9000)));
    EXPECT_EQ(estimator.offset_ns(), 5000);  // still in the window
  }
  ASSERT_TRUE(estimator.add_sample(exchange(4'000'000, 1000, 0, 1000, 9000)));
  EXPECT_EQ(estimator.samples_in_window(), 4u);
  EXPECT_EQ(estimator.offset_ns(), 9000);  // the old best sample aged out: the clock moved on
  EXPECT_EQ(estimator.rtt_ns(), 2000);
}

TEST(ClockSync, TiesPreferTheNewestSample) {
  ClockOffsetEstimator estimator(8);
  ASSERT_TRUE(estimator.add_sample(exchange(0, 1000, 0, 1000, 100)));
  ASSERT_TRUE(estimator.add_sample(exchange(10'000, 1000, 0, 1000, 200)));
  EXPECT_EQ(estimator.offset_ns(), 200);
}

TEST(ClockSync, EchoFormMatchesTheFourTimestampForm) {
  const ClockSample s = exchange(50'000, 3'000, 1'500, 7'000);
  ClockOffsetEstimator from_sample;
  ClockOffsetEstimator from_echo;
  ASSERT_TRUE(from_sample.add_sample(s));
  ASSERT_TRUE(from_echo.add_echo(s.t0_ns, s.t2_ns - s.t1_ns, s.t2_ns, s.t3_ns));
  EXPECT_EQ(from_sample.estimate(), from_echo.estimate());
}

TEST(ClockSync, ConvertsBetweenClocks) {
  ClockOffsetEstimator estimator;
  ASSERT_TRUE(estimator.add_sample(exchange(0, 1000, 0, 1000, 250'000)));
  EXPECT_EQ(estimator.server_to_client_ns(1'250'000), 1'000'000);
  EXPECT_EQ(estimator.client_to_server_ns(1'000'000), 1'250'000);
  estimator.reset();
  EXPECT_FALSE(estimator.has_estimate());
  EXPECT_EQ(estimator.server_to_client_ns(42), 42);
}

TEST(ClockSync, ZeroWindowIsTreatedAsOne) {
  ClockOffsetEstimator estimator(0);
  EXPECT_EQ(estimator.window(), 1u);
  ASSERT_TRUE(estimator.add_sample(exchange(0, 10, 0, 10, 1)));
  ASSERT_TRUE(estimator.add_sample(exchange(100, 500, 0, 500, 2)));
  EXPECT_EQ(estimator.offset_ns(), 2);  // only the newest sample is kept
}

TEST(Clock, VirtualClockMovesOnlyWhenTold) {
  VirtualClock clock(100);
  const Clock& as_clock = clock;
  EXPECT_EQ(as_clock.now_ns(), 100);
  clock.advance_ns(50);
  EXPECT_EQ(as_clock.now_ns(), 150);
  clock.set_ns(7);
  EXPECT_EQ(as_clock.now_ns(), 7);
}

TEST(Clock, SteadyClockIsMonotonic) {
  SteadyClock clock;
  int64_t previous = clock.now_ns();
  for (int i = 0; i < 1000; ++i) {
    const int64_t now = clock.now_ns();
    EXPECT_GE(now, previous);
    previous = now;
  }
}

}  // namespace
}  // namespace dhr::net
