// SendRateController: the loss a client's reports imply caps the session's trace rate just under what got
// through; low loss lifts the cap additively until it is gone; a disabled controller never caps; a 32-bit
// counter that wraps is no loss.
#include <gtest/gtest.h>

#include "session/rate_control.hpp"

namespace dhr::server {
namespace {

constexpr int64_t kS = 1'000'000'000;

RateControlConfig enabled() {
  RateControlConfig c;
  c.enabled = true;
  return c;
}

TEST(SendRateController, HalfLostCapsUnderWhatGotThroughAndLowLossLiftsTheCap) {
  SendRateController rate(enabled());
  rate.on_report(0, 0, 0, 0);  // the first report only sets the baseline
  EXPECT_FALSE(rate.cap_fps());
  EXPECT_TRUE(rate.due(5, 0));
  // One second: 2000 datagrams sent, 1000 arrived, 90 frames traced.
  rate.on_report(kS, 1000, 2000, 90);
  EXPECT_DOUBLE_EQ(rate.last_loss(), 0.5);
  ASSERT_TRUE(rate.cap_fps());
  EXPECT_NEAR(*rate.cap_fps(), 90 * 0.5 * 0.85, 1e-9);
  EXPECT_EQ(rate.decreases(), 1u);
  const int64_t period = static_cast<int64_t>(1e9 / *rate.cap_fps());
  EXPECT_EQ(rate.next_due_ns(10 * kS), 10 * kS + period);
  EXPECT_FALSE(rate.due(10 * kS + period - 1, 10 * kS));
  EXPECT_TRUE(rate.due(10 * kS + period, 10 * kS));
  // Loss in between the thresholds: nothing changes.
  const double cap = *rate.cap_fps();
  rate.on_report(2 * kS, 1000 + 950, 3000, 128);
  EXPECT_NEAR(rate.last_loss(), 0.05, 1e-12);
  EXPECT_DOUBLE_EQ(*rate.cap_fps(), cap);
  // No loss: +2 per second until above the maximum, then no cap.
  rate.on_report(3 * kS, 1950 + 1000, 4000, 166);
  EXPECT_NEAR(*rate.cap_fps(), cap + 2.0, 1e-9);
  uint64_t sent = 4000, received = 2950, frames = 166;
  for (int s = 4; s < 200 && rate.cap_fps(); ++s) {
    sent += 1000;
    received += 1000;
    frames += 40;
    rate.on_report(s * kS, static_cast<uint32_t>(received), sent, frames);
  }
  EXPECT_FALSE(rate.cap_fps());
}

TEST(SendRateController, NeverBelowTheMinimumNorWhenDisabledAndWrappingIsNoLoss) {
  SendRateController rate(enabled());
  rate.on_report(0, 0, 0, 0);
  rate.on_report(kS, 0, 1000, 10);  // everything lost
  ASSERT_TRUE(rate.cap_fps());
  EXPECT_DOUBLE_EQ(*rate.cap_fps(), 2.0);
  SendRateController wrapping(enabled());
  wrapping.on_report(0, 0xFFFFFF00u, 500, 0);
  wrapping.on_report(kS, 0x00000100u, 1012, 90);  // 512 received across the wrap, 512 sent
  EXPECT_DOUBLE_EQ(wrapping.last_loss(), 0.0);
  EXPECT_FALSE(wrapping.cap_fps());
  SendRateController off;  // RateControlConfig{} is disabled
  off.on_report(0, 0, 0, 0);
  off.on_report(kS, 0, 1000, 90);
  EXPECT_FALSE(off.cap_fps());
  EXPECT_TRUE(off.due(0, 0));
}

}  // namespace
}  // namespace dhr::server
