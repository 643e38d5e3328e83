#include "net/impairment_cli.hpp"

#include <CLI/CLI.hpp>

#include <charconv>
#include <cstdio>
#include <vector>

namespace dhr::net {
namespace {

constexpr const char* kGroup = "Network impairment";

bool parse_double(std::string_view text, double& out) {
  // std::from_chars for double exists in GCC 12's libstdc++; trim spaces around commas first.
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  if (text.empty()) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size();
}

std::string check_fraction(const std::string& text) {
  double value = 0.0;
  if (!parse_double(text, value) || !(value >= 0.0 && value <= 1.0)) return "must be a fraction in 0..1, got '" + text + "'";
  return {};
}

std::string check_ms(const std::string& text) {
  double value = 0.0;
  if (!parse_double(text, value) || !(value >= 0.0 && value <= kMaxImpairmentDelayMs)) {
    char limit[32];
    std::snprintf(limit, sizeof(limit), "%g", kMaxImpairmentDelayMs);
    return "must be a number of milliseconds in 0.." + std::string(limit) + ", got '" + text + "'";
  }
  return {};
}

}  // namespace

bool parse_burst_loss(std::string_view text, ImpairmentParams& params, std::string* out_error) {
  std::vector<double> values;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string_view part = text.substr(start, comma == std::string_view::npos ? comma : comma - start);
    double value = 0.0;
    if (!parse_double(part, value)) {
      if (out_error) *out_error = "expected P_GOOD_TO_BAD,P_BAD_TO_GOOD[,LOSS_IN_BAD], got '" + std::string(text) + "'";
      return false;
    }
    values.push_back(value);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (values.size() < 2 || values.size() > 3) {
    if (out_error) *out_error = "expected 2 or 3 comma-separated values, got '" + std::string(text) + "'";
    return false;
  }
  ImpairmentParams candidate = params;
  candidate.burst_p_good_to_bad = values[0];
  candidate.burst_p_bad_to_good = values[1];
  candidate.burst_loss_in_bad = values.size() == 3 ? values[2] : 1.0;
  // Only the burst fields are checked here: the other options may not be parsed yet.
  ImpairmentParams burst_only;
  burst_only.burst_p_good_to_bad = candidate.burst_p_good_to_bad;
  burst_only.burst_p_bad_to_good = candidate.burst_p_bad_to_good;
  burst_only.burst_loss_in_bad = candidate.burst_loss_in_bad;
  const std::string error = burst_only.validate();
  if (!error.empty()) {
    if (out_error) *out_error = error;
    return false;
  }
  params = candidate;
  return true;
}

void add_impairment_options(CLI::App& app, ImpairmentParams& params) {
  app.add_option("--net-delay", params.delay_ms, "Impairment: fixed one-way delay added to every datagram sent")
      ->type_name("MS")
      ->check(check_ms, "MS")
      ->group(kGroup);
  app.add_option("--net-jitter", params.jitter_ms,
                 "Impairment: delay variation (uniform: +-MS; normal: standard deviation MS); keeps order")
      ->type_name("MS")
      ->check(check_ms, "MS")
      ->group(kGroup);
  app.add_option_function<std::string>(
         "--net-jitter-dist",
         [&params](const std::string& text) {
           params.jitter_distribution =
               text == "normal" ? JitterDistribution::kNormal : JitterDistribution::kUniform;
         },
         "Impairment: jitter distribution (default uniform)")
      ->type_name("uniform|normal")
      ->check(CLI::IsMember({"uniform", "normal"}))
      ->group(kGroup);
  app.add_option("--net-loss", params.loss, "Impairment: random loss probability per datagram")
      ->type_name("FRACTION")
      ->check(check_fraction, "FRACTION")
      ->group(kGroup);
  app.add_option_function<std::string>(
         "--net-burst-loss",
         [&params](const std::string& text) { parse_burst_loss(text, params); },
         "Impairment: bursty loss, Gilbert-Elliott per-datagram transition probabilities good->bad and "
         "bad->good; optional loss probability in the bad state (default 1)")
      ->type_name("P_GOOD_TO_BAD,P_BAD_TO_GOOD[,LOSS_IN_BAD]")
      ->check(
          [](const std::string& text) {
            ImpairmentParams scratch;
            std::string error;
            return parse_burst_loss(text, scratch, &error) ? std::string() : error;
          },
          "BURST")
      ->group(kGroup);
  app.add_option("--net-reorder", params.reorder,
                 "Impairment: probability a datagram is held back (--net-reorder-delay) and overtaken")
      ->type_name("FRACTION")
      ->check(check_fraction, "FRACTION")
      ->group(kGroup);
  app.add_option("--net-reorder-delay", params.reorder_delay_ms,
                 "Impairment: extra delay of a reordered datagram (default 20)")
      ->type_name("MS")
      ->check(
          [](const std::string& text) {
            double value = 0.0;
            if (parse_double(text, value) && value <= 0.0) return std::string("must be > 0 ms");
            return check_ms(text);
          },
          "MS")
      ->group(kGroup);
  app.add_option("--net-duplicate", params.duplicate, "Impairment: probability a datagram is delivered twice")
      ->type_name("FRACTION")
      ->check(check_fraction, "FRACTION")
      ->group(kGroup);
  app.add_option("--net-seed", params.seed, "Impairment: random seed (same seed, same loss/delay schedule)")
      ->type_name("N")
      ->check(
          [](const std::string& text) {
            // CLI11 would wrap "-3" around to a huge unsigned value; only plain digits are a seed.
            const bool digits = !text.empty() && text.size() <= 20 &&
                                text.find_first_not_of("0123456789") == std::string::npos;
            return digits ? std::string() : "must be a non-negative integer, got '" + text + "'";
          },
          "N")
      ->group(kGroup);
}

}  // namespace dhr::net
