#include "net/impairment_cli.hpp"

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace dhr::net {
namespace {

// Parses args (without the program name) into params; returns CLI11's error text, "" on success.
std::string parse(std::vector<std::string> args, ImpairmentParams& params) {
  CLI::App app("test");
  add_impairment_options(app, params);
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them back to front
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return {};
}

TEST(ImpairmentCli, ParsesEveryOption) {
  ImpairmentParams params;
  ASSERT_EQ(parse({"--net-delay", "50", "--net-jitter", "20", "--net-jitter-dist", "normal", "--net-loss", "0.3",
                   "--net-burst-loss", "0.01,0.25", "--net-reorder", "0.05", "--net-reorder-delay", "15",
                   "--net-duplicate", "0.02", "--net-seed", "1234"},
                  params),
            "");
  EXPECT_DOUBLE_EQ(params.delay_ms, 50.0);
  EXPECT_DOUBLE_EQ(params.jitter_ms, 20.0);
  EXPECT_EQ(params.jitter_distribution, JitterDistribution::kNormal);
  EXPECT_DOUBLE_EQ(params.loss, 0.3);
  EXPECT_DOUBLE_EQ(params.burst_p_good_to_bad, 0.01);
  EXPECT_DOUBLE_EQ(params.burst_p_bad_to_good, 0.25);
  EXPECT_DOUBLE_EQ(params.burst_loss_in_bad, 1.0);
  EXPECT_DOUBLE_EQ(params.reorder, 0.05);
  EXPECT_DOUBLE_EQ(params.reorder_delay_ms, 15.0);
  EXPECT_DOUBLE_EQ(params.duplicate, 0.02);
  EXPECT_EQ(params.seed, 1234u);
  EXPECT_EQ(params.validate(), "");
  EXPECT_TRUE(params.active());
}

TEST(ImpairmentCli, NoOptionsKeepTheDefaults) {
  ImpairmentParams params;
  params.seed = 99;
  ASSERT_EQ(parse({}, params), "");
  ImpairmentParams expected;
  expected.seed = 99;
  EXPECT_EQ(params, expected);
  EXPECT_FALSE(params.active());
}

TEST(ImpairmentCli, EqualsFormAndThreeValueBurst) {
  ImpairmentParams params;
  ASSERT_EQ(parse({"--net-burst-loss=0.1,0.5,0.8", "--net-loss=0"}, params), "");
  EXPECT_DOUBLE_EQ(params.burst_p_good_to_bad, 0.1);
  EXPECT_DOUBLE_EQ(params.burst_p_bad_to_good, 0.5);
  EXPECT_DOUBLE_EQ(params.burst_loss_in_bad, 0.8);
}

TEST(ImpairmentCli, RejectsOutOfRangeAndMalformedValues) {
  const std::vector<std::vector<std::string>> bad = {
      {"--net-loss", "1.5"},         {"--net-loss", "-0.1"},           {"--net-loss", "nan"},
      {"--net-delay", "-5"},         {"--net-delay", "1e9"},           {"--net-jitter", "abc"},
      {"--net-jitter-dist", "pareto"}, {"--net-burst-loss", "0.1"},    {"--net-burst-loss", "0.1,0"},
      {"--net-burst-loss", "a,b"},   {"--net-burst-loss", "0.1,0.2,0.3,0.4"}, {"--net-reorder", "2"},
      {"--net-reorder-delay", "0"},  {"--net-duplicate", "-1"},        {"--net-seed", "-3"},
  };
  for (const auto& args : bad) {
    ImpairmentParams params;
    const std::string error = parse(args, params);
    EXPECT_NE(error, "") << args[0] << " " << args[1];
  }
}

TEST(ImpairmentCli, ParseBurstLossReportsWhy) {
  ImpairmentParams params;
  std::string error;
  EXPECT_FALSE(parse_burst_loss("0.5", params, &error));
  EXPECT_NE(error.find("2 or 3"), std::string::npos) << error;
  EXPECT_FALSE(parse_burst_loss("0.5,0", params, &error));
  EXPECT_NE(error.find("never recovers"), std::string::npos) << error;
  EXPECT_FALSE(parse_burst_loss("x,0.5", params, &error));
  EXPECT_EQ(params, ImpairmentParams());  // untouched on failure
  EXPECT_TRUE(parse_burst_loss(" 0.05 , 0.5 ", params, &error));
  EXPECT_DOUBLE_EQ(params.burst_p_good_to_bad, 0.05);
  EXPECT_TRUE(parse_burst_loss("0,0", params, &error));  // disabled burst loss is fine
}

}  // namespace
}  // namespace dhr::net
