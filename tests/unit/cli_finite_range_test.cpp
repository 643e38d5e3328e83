// dhr::cli::FiniteRange: finite numbers within the range pass; NaN, infinities, non-numbers and values out of
// range are parse errors (CLI::Range lets NaN through).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli/finite_range.hpp"

namespace dhr::cli {
namespace {

bool parses(const std::string& value, double min, double max, double* out = nullptr) {
  CLI::App app;
  double v = -1.0;
  app.add_option("--x", v)->check(FiniteRange(min, max));
  std::vector<std::string> args = {value, "--x"};  // CLI11 takes them in reverse order
  try {
    app.parse(args);
  } catch (const CLI::ParseError&) {
    return false;
  }
  if (out) *out = v;
  return true;
}

TEST(FiniteRange, AcceptsFiniteValuesInRangeOnly) {
  double v = 0.0;
  EXPECT_TRUE(parses("0.5", 0.1, 1.0, &v));
  EXPECT_EQ(v, 0.5);
  EXPECT_TRUE(parses("0.1", 0.1, 1.0));
  EXPECT_TRUE(parses("1", 0.1, 1.0));
  for (const char* bad : {"nan", "NaN", "-nan", "inf", "-inf", "1e400", "0.05", "1.01", "abc", ""}) {
    EXPECT_FALSE(parses(bad, 0.1, 1.0)) << bad;
  }
}

TEST(FiniteRange, IntegerOptionsKeepTheirParsing) {
  CLI::App app;
  unsigned n = 0;
  app.add_option("--n", n)->check(FiniteRange(1u, 100u));
  std::vector<std::string> ok = {"42", "--n"};
  app.parse(ok);
  EXPECT_EQ(n, 42u);
  for (const char* bad : {"0", "101", "nan", "2.5"}) {
    CLI::App again;
    unsigned m = 0;
    again.add_option("--n", m)->check(FiniteRange(1u, 100u));
    std::vector<std::string> args = {bad, "--n"};
    EXPECT_THROW(again.parse(args), CLI::ParseError) << bad;
  }
}

}  // namespace
}  // namespace dhr::cli
