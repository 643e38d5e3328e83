#include "net/clock.hpp"
#include "net/impairment.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace dhr::net {
namespace {

constexpr int kPackets = 100'000;
constexpr int64_t kSpacingNs = 1'000'000;  // one datagram per ms

std::vector<ImpairmentDecision> run(const ImpairmentParams& params, int count = kPackets,
                                    int64_t spacing_ns = kSpacingNs) {
  ImpairmentModel model(params);
  std::vector<ImpairmentDecision> decisions;
  decisions.reserve(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) decisions.push_back(model.next(i * spacing_ns));
  return decisions;
}

bool same_decision(const ImpairmentDecision& a, const ImpairmentDecision& b) {
  return a.sequence == b.sequence && a.delivery_count == b.delivery_count && a.delivery_ns == b.delivery_ns &&
         a.lost == b.lost && a.lost_in_burst == b.lost_in_burst && a.reordered == b.reordered &&
         a.duplicated == b.duplicated;
}

// Mean length of runs of consecutive lost datagrams.
double mean_loss_run(const std::vector<ImpairmentDecision>& decisions) {
  uint64_t runs = 0;
  uint64_t lost = 0;
  bool in_run = false;
  for (const ImpairmentDecision& d : decisions) {
    if (d.lost) {
      ++lost;
      if (!in_run) ++runs;
    }
    in_run = d.lost;
  }
  return runs == 0 ? 0.0 : static_cast<double>(lost) / static_cast<double>(runs);
}

// |count - n p| within 5 binomial standard deviations.
void expect_binomial(uint64_t count, uint64_t n, double p) {
  const double mean = static_cast<double>(n) * p;
  const double sd = std::sqrt(static_cast<double>(n) * p * (1.0 - p));
  EXPECT_NEAR(static_cast<double>(count), mean, 5.0 * sd) << "n=" << n << " p=" << p;
}

ImpairmentParams bad_network() {  // the integration setting
  ImpairmentParams p;
  p.delay_ms = 50.0;
  p.jitter_ms = 20.0;
  p.loss = 0.3;
  p.reorder = 0.05;
  p.duplicate = 0.05;
  p.seed = 42;
  return p;
}

TEST(Impairment, DefaultParamsArePerfectAndValid) {
  const ImpairmentParams params;
  EXPECT_FALSE(params.active());
  EXPECT_EQ(params.validate(), "");
  EXPECT_EQ(params.describe(), "none");
  const auto decisions = run(params, 1000);
  for (const ImpairmentDecision& d : decisions) {
    ASSERT_EQ(d.delivery_count, 1);
    EXPECT_EQ(d.delivery_ns[0], static_cast<int64_t>(d.sequence) * kSpacingNs);
  }
}

TEST(Impairment, SameSeedSameScheduleOtherSeedOtherSchedule) {
  const ImpairmentParams params = bad_network();
  const auto a = run(params, 20'000);
  const auto b = run(params, 20'000);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) ASSERT_TRUE(same_decision(a[i], b[i])) << "datagram " << i;

  ImpairmentParams other = params;
  other.seed = 43;
  const auto c = run(other, 20'000);
  size_t differing = 0;
  for (size_t i = 0; i < a.size(); ++i) differing += same_decision(a[i], c[i]) ? 0 : 1;
  EXPECT_GT(differing, a.size() / 4);

  ImpairmentModel model(params);
  std::vector<ImpairmentDecision> first;
  for (int i = 0; i < 100; ++i) first.push_back(model.next(i * kSpacingNs));
  model.reset();
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(same_decision(first[static_cast<size_t>(i)], model.next(i * kSpacingNs)));
}

TEST(Impairment, RandomLossRateMatchesWithFixedSeed) {
  ImpairmentParams params;
  params.loss = 0.1;
  params.seed = 1;
  ImpairmentModel model(params);
  for (int i = 0; i < kPackets; ++i) model.next(i * kSpacingNs);
  const ImpairmentStats& stats = model.stats();
  EXPECT_EQ(stats.sent, static_cast<uint64_t>(kPackets));
  expect_binomial(stats.lost, kPackets, 0.1);
  EXPECT_EQ(stats.lost, 9'927u);  // the deterministic count for seed 1 (any platform)
  EXPECT_EQ(stats.lost_random, stats.lost);
  EXPECT_EQ(stats.lost_burst, 0u);
  EXPECT_EQ(stats.deliveries, stats.sent - stats.lost);
  EXPECT_DOUBLE_EQ(params.expected_loss(), 0.1);
}

TEST(Impairment, LossExtremes) {
  ImpairmentParams all;
  all.loss = 1.0;
  ImpairmentModel model(all);
  for (int i = 0; i < 1000; ++i) EXPECT_TRUE(model.next(i).lost);
  EXPECT_EQ(model.stats().deliveries, 0u);
}

TEST(Impairment, BurstLossHasLongerRunsThanRandomLossAtTheSameMean) {
  ImpairmentParams burst;
  burst.burst_p_good_to_bad = 0.02;
  burst.burst_p_bad_to_good = 0.18;  // stationary P(bad) = 0.02 / 0.2 = 0.1, mean burst 1 / 0.18
  burst.seed = 5;
  ImpairmentParams random;
  random.loss = burst.expected_loss();
  random.seed = 5;
  EXPECT_NEAR(burst.expected_loss(), 0.1, 1e-12);

  const auto burst_decisions = run(burst);
  const auto random_decisions = run(random);
  const auto lost = [](const std::vector<ImpairmentDecision>& ds) {
    return static_cast<uint64_t>(std::count_if(ds.begin(), ds.end(), [](const auto& d) { return d.lost; }));
  };
  // Burst loss is correlated, so its count varies more than a binomial: allow +-15% of the mean.
  EXPECT_NEAR(static_cast<double>(lost(burst_decisions)), 0.1 * kPackets, 0.015 * kPackets);
  expect_binomial(lost(random_decisions), kPackets, 0.1);

  const double burst_run = mean_loss_run(burst_decisions);
  const double random_run = mean_loss_run(random_decisions);
  EXPECT_NEAR(random_run, 1.0 / 0.9, 0.05);   // geometric runs
  EXPECT_NEAR(burst_run, 1.0 / 0.18, 0.5);    // the bad state's mean sojourn
  EXPECT_GT(burst_run, 3.0 * random_run);
  for (const auto& d : burst_decisions) {
    if (d.lost) {
      EXPECT_TRUE(d.lost_in_burst);
    }
  }
}

TEST(Impairment, BurstStateWithPartialLoss) {
  ImpairmentParams params;
  params.burst_p_good_to_bad = 0.05;
  params.burst_p_bad_to_good = 0.2;
  params.burst_loss_in_bad = 0.5;
  params.loss = 0.02;
  params.seed = 9;
  ImpairmentModel model(params);
  for (int i = 0; i < kPackets; ++i) model.next(i * kSpacingNs);
  const ImpairmentStats& stats = model.stats();
  EXPECT_EQ(stats.lost, stats.lost_random + stats.lost_burst);
  EXPECT_GT(stats.lost_random, 0u);
  EXPECT_GT(stats.lost_burst, 0u);
  // 1 - 0.98 * (1 - 0.2 * 0.5) = 0.118
  EXPECT_NEAR(params.expected_loss(), 0.118, 1e-12);
  EXPECT_NEAR(static_cast<double>(stats.lost) / kPackets, 0.118, 0.015);
}

TEST(Impairment, UniformDelayAndJitterStayInBoundsWithTheRightMoments) {
  ImpairmentParams params;
  params.delay_ms = 50.0;
  params.jitter_ms = 20.0;
  params.seed = 3;
  // 100 ms apart: the FIFO rule never binds, so the raw jitter distribution is visible.
  const auto decisions = run(params, 50'000, 100 * kNsPerMs);
  double sum = 0.0;
  double sum_sq = 0.0;
  for (const ImpairmentDecision& d : decisions) {
    ASSERT_EQ(d.delivery_count, 1);
    const double delay_ms = static_cast<double>(d.delivery_ns[0] - static_cast<int64_t>(d.sequence) * 100 * kNsPerMs) / 1e6;
    ASSERT_GE(delay_ms, 30.0);
    ASSERT_LE(delay_ms, 70.0);
    sum += delay_ms;
    sum_sq += delay_ms * delay_ms;
  }
  const double n = static_cast<double>(decisions.size());
  const double mean = sum / n;
  const double sd = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(mean, 50.0, 0.3);
  EXPECT_NEAR(sd, 20.0 / std::sqrt(3.0), 0.3);  // uniform on [-20, 20]
}

TEST(Impairment, NormalJitterHasTheRequestedStandardDeviationAndIsClamped) {
  ImpairmentParams params;
  params.delay_ms = 100.0;
  params.jitter_ms = 10.0;
  params.jitter_distribution = JitterDistribution::kNormal;
  params.seed = 4;
  const auto decisions = run(params, 50'000, 200 * kNsPerMs);
  double sum = 0.0;
  double sum_sq = 0.0;
  for (const ImpairmentDecision& d : decisions) {
    const double delay_ms = static_cast<double>(d.delivery_ns[0] - static_cast<int64_t>(d.sequence) * 200 * kNsPerMs) / 1e6;
    ASSERT_GE(delay_ms, 60.0);   // 100 - 4 sigma
    ASSERT_LE(delay_ms, 140.0);  // 100 + 4 sigma
    sum += delay_ms;
    sum_sq += delay_ms * delay_ms;
  }
  const double n = static_cast<double>(decisions.size());
  const double mean = sum / n;
  EXPECT_NEAR(mean, 100.0, 0.3);
  EXPECT_NEAR(std::sqrt(sum_sq / n - mean * mean), 10.0, 0.3);
}

TEST(Impairment, JitterNeverGoesBelowZeroDelay) {
  ImpairmentParams params;
  params.delay_ms = 1.0;
  params.jitter_ms = 30.0;
  const auto decisions = run(params, 10'000, 100 * kNsPerMs);
  for (const ImpairmentDecision& d : decisions) {
    EXPECT_GE(d.delivery_ns[0], static_cast<int64_t>(d.sequence) * 100 * kNsPerMs);
  }
}

TEST(Impairment, JitterAloneKeepsOrderAndBounds) {
  ImpairmentParams params;
  params.delay_ms = 50.0;
  params.jitter_ms = 20.0;
  params.seed = 11;
  const auto decisions = run(params, kPackets, 100'000);  // 0.1 ms apart: jitter would reorder without FIFO
  int64_t previous = 0;
  for (const ImpairmentDecision& d : decisions) {
    const int64_t send = static_cast<int64_t>(d.sequence) * 100'000;
    ASSERT_GE(d.delivery_ns[0], previous);
    ASSERT_GE(d.delivery_ns[0] - send, 30 * kNsPerMs);
    ASSERT_LE(d.delivery_ns[0] - send, 70 * kNsPerMs);
    previous = d.delivery_ns[0];
  }
}

TEST(Impairment, ReorderingHappensAtItsRateAndIsObservable) {
  ImpairmentParams params;
  params.delay_ms = 10.0;
  params.jitter_ms = 2.0;
  params.reorder = 0.05;
  params.reorder_delay_ms = 20.0;
  params.seed = 6;
  ImpairmentModel model(params);
  std::vector<ImpairmentDecision> decisions;
  for (int i = 0; i < kPackets; ++i) decisions.push_back(model.next(i * kSpacingNs));
  expect_binomial(model.stats().reordered, kPackets, 0.05);

  int64_t previous_in_order = 0;
  for (size_t i = 0; i < decisions.size(); ++i) {
    const ImpairmentDecision& d = decisions[i];
    if (!d.reordered) {
      ASSERT_GE(d.delivery_ns[0], previous_in_order);  // the rest stay FIFO
      previous_in_order = d.delivery_ns[0];
      continue;
    }
    const int64_t send = static_cast<int64_t>(i) * kSpacingNs;
    EXPECT_GE(d.delivery_ns[0] - send, 28 * kNsPerMs);
    EXPECT_LE(d.delivery_ns[0] - send, 32 * kNsPerMs);
    // Sent 1 ms apart and held back 20 ms: the next datagram overtakes it.
    if (i + 1 < decisions.size() && !decisions[i + 1].reordered) {
      EXPECT_LT(decisions[i + 1].delivery_ns[0], d.delivery_ns[0]);
    }
  }
}

TEST(Impairment, DuplicationHappensAtItsRate) {
  ImpairmentParams params;
  params.delay_ms = 5.0;
  params.jitter_ms = 1.0;
  params.duplicate = 0.1;
  params.seed = 8;
  ImpairmentModel model(params);
  for (int i = 0; i < kPackets; ++i) {
    const ImpairmentDecision d = model.next(i * kSpacingNs);
    if (d.duplicated) {
      ASSERT_EQ(d.delivery_count, 2);
      EXPECT_GE(d.delivery_ns[1], d.delivery_ns[0]);
      EXPECT_LE(d.delivery_ns[1] - d.delivery_ns[0], 1 * kNsPerMs);
    } else {
      ASSERT_EQ(d.delivery_count, 1);
    }
  }
  expect_binomial(model.stats().duplicated, kPackets, 0.1);
  EXPECT_EQ(model.stats().deliveries, kPackets + model.stats().duplicated);
}

TEST(Impairment, DecisionsAreIndependentAcrossImpairments) {
  // Adding duplication and reordering must not change which datagrams are lost.
  ImpairmentParams loss_only;
  loss_only.loss = 0.2;
  loss_only.seed = 77;
  ImpairmentParams everything = loss_only;
  everything.duplicate = 0.3;
  everything.reorder = 0.3;
  everything.jitter_ms = 5.0;
  const auto a = run(loss_only, 10'000);
  const auto b = run(everything, 10'000);
  for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i].lost, b[i].lost) << i;
}

TEST(Impairment, CombinedBadNetworkCountersAddUp) {
  ImpairmentModel model(bad_network());
  for (int i = 0; i < kPackets; ++i) model.next(i * 11 * kNsPerMs / 2);
  const ImpairmentStats& s = model.stats();
  EXPECT_EQ(s.sent, static_cast<uint64_t>(kPackets));
  EXPECT_EQ(s.lost, s.lost_random + s.lost_burst);
  EXPECT_EQ(s.deliveries, s.sent - s.lost + s.duplicated);
  expect_binomial(s.lost, kPackets, 0.3);
  expect_binomial(s.reordered, s.sent - s.lost, 0.05);
  expect_binomial(s.duplicated, s.sent - s.lost, 0.05);
}

TEST(Impairment, InvalidParamsAreRejectedWithTheOptionName) {
  const auto error_of = [](auto mutate) {
    ImpairmentParams p;
    mutate(p);
    return p.validate();
  };
  EXPECT_NE(error_of([](ImpairmentParams& p) { p.delay_ms = -1; }).find("--net-delay"), std::string::npos);
  EXPECT_NE(error_of([](ImpairmentParams& p) { p.delay_ms = NAN; }).find("--net-delay"), std::string::npos);
  EXPECT_NE(error_of([](ImpairmentParams& p) { p.jitter_ms = INFINITY; }).find("--net-jitter"), std::string::npos);
  EXPECT_NE(error_of([](ImpairmentParams& p) { p.loss = 1.5; }).find("--net-loss"), std::string::npos);
  EXPECT_NE(error_of([](ImpairmentParams& p) { p.burst_p_good_to_bad = -0.1; }).find("--net-burst-loss"),
            std::string::npos);
  EXPECT_NE(error_of([](ImpairmentParams& p) {
              p.burst_p_good_to_bad = 0.1;
              p.burst_p_bad_to_good = 0.0;
            }).find("never recovers"),
            std::string::npos);
  EXPECT_NE(error_of([](ImpairmentParams& p) { p.reorder = 2; }).find("--net-reorder"), std::string::npos);
  EXPECT_NE(error_of([](ImpairmentParams& p) { p.reorder_delay_ms = 0; }).find("--net-reorder-delay"),
            std::string::npos);
  EXPECT_NE(error_of([](ImpairmentParams& p) { p.duplicate = -0.5; }).find("--net-duplicate"), std::string::npos);
  EXPECT_NE(error_of([](ImpairmentParams& p) { p.jitter_distribution = static_cast<JitterDistribution>(9); })
                .find("--net-jitter-dist"),
            std::string::npos);

  ImpairmentParams bad;
  bad.loss = -1;
  EXPECT_THROW(ImpairmentModel{bad}, std::invalid_argument);
}

TEST(Impairment, DescribeNamesTheSettings) {
  const std::string text = bad_network().describe();
  EXPECT_NE(text.find("delay=50ms"), std::string::npos) << text;
  EXPECT_NE(text.find("jitter=20ms(uniform)"), std::string::npos) << text;
  EXPECT_NE(text.find("loss=0.3"), std::string::npos) << text;
  EXPECT_NE(text.find("seed=42"), std::string::npos) << text;
}

}  // namespace
}  // namespace dhr::net
