#include "net/impairment.hpp"

#include "net/clock.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace dhr::net {
namespace {

// Independent decision streams per datagram: each has its own hash input, so enabling one impairment
// never shifts the random numbers another one sees.
enum class Stream : uint64_t {
  kBurstTransition = 1,
  kBurstLoss,
  kLoss,
  kJitterA,
  kJitterB,
  kReorder,
  kDuplicate,
  kDuplicateGap,
};

// SplitMix64's finalizer: a bijective 64-bit mix with good avalanche.
uint64_t mix64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebull;
  x ^= x >> 31;
  return x;
}

// Uniform in [0, 1) with 53 random bits.
double uniform01(uint64_t seed, uint64_t sequence, Stream stream) {
  const uint64_t key = mix64(seed + 0x9e3779b97f4a7c15ull) ^ mix64(sequence * 16 + static_cast<uint64_t>(stream));
  return static_cast<double>(mix64(key) >> 11) * 0x1.0p-53;
}

int64_t ms_to_ns(double ms) { return static_cast<int64_t>(std::llround(ms * static_cast<double>(kNsPerMs))); }

bool is_probability(double p) { return std::isfinite(p) && p >= 0.0 && p <= 1.0; }

bool is_duration(double ms) { return std::isfinite(ms) && ms >= 0.0 && ms <= kMaxImpairmentDelayMs; }

}  // namespace

const char* to_string(JitterDistribution distribution) {
  switch (distribution) {
    case JitterDistribution::kUniform:
      return "uniform";
    case JitterDistribution::kNormal:
      return "normal";
  }
  return "unknown";
}

bool ImpairmentParams::active() const {
  return delay_ms > 0.0 || jitter_ms > 0.0 || loss > 0.0 || burst_p_good_to_bad > 0.0 || reorder > 0.0 ||
         duplicate > 0.0;
}

std::string ImpairmentParams::validate() const {
  char limit[32];
  std::snprintf(limit, sizeof(limit), "%g", kMaxImpairmentDelayMs);
  if (!is_duration(delay_ms)) return std::string("--net-delay must be a number of ms in 0..") + limit;
  if (!is_duration(jitter_ms)) return std::string("--net-jitter must be a number of ms in 0..") + limit;
  if (jitter_distribution != JitterDistribution::kUniform && jitter_distribution != JitterDistribution::kNormal) {
    return "--net-jitter-dist must be uniform or normal";
  }
  if (!is_probability(loss)) return "--net-loss must be a fraction in 0..1";
  if (!is_probability(burst_p_good_to_bad) || !is_probability(burst_p_bad_to_good)) {
    return "--net-burst-loss probabilities must be fractions in 0..1";
  }
  if (burst_p_good_to_bad > 0.0 && burst_p_bad_to_good <= 0.0) {
    return "--net-burst-loss: P_BAD_TO_GOOD must be > 0 (otherwise the link never recovers)";
  }
  if (!is_probability(burst_loss_in_bad)) return "--net-burst-loss: LOSS_IN_BAD must be a fraction in 0..1";
  if (!is_probability(reorder)) return "--net-reorder must be a fraction in 0..1";
  if (!is_duration(reorder_delay_ms) || reorder_delay_ms <= 0.0) {
    return std::string("--net-reorder-delay must be a number of ms in (0..") + limit + "]";
  }
  if (!is_probability(duplicate)) return "--net-duplicate must be a fraction in 0..1";
  return {};
}

std::string ImpairmentParams::describe() const {
  if (!active()) return "none";
  char text[320];
  std::snprintf(text, sizeof(text),
                "delay=%gms jitter=%gms(%s) loss=%g burst=%g,%g,%g reorder=%g(+%gms) duplicate=%g seed=%llu",
                delay_ms, jitter_ms, to_string(jitter_distribution), loss, burst_p_good_to_bad,
                burst_p_bad_to_good, burst_loss_in_bad, reorder, reorder_delay_ms, duplicate,
                static_cast<unsigned long long>(seed));
  return text;
}

double ImpairmentParams::expected_loss() const {
  double pi_bad = 0.0;
  if (burst_p_good_to_bad > 0.0) pi_bad = burst_p_good_to_bad / (burst_p_good_to_bad + burst_p_bad_to_good);
  return 1.0 - (1.0 - loss) * (1.0 - pi_bad * burst_loss_in_bad);
}

ImpairmentModel::ImpairmentModel(const ImpairmentParams& params) : params_(params) {
  const std::string error = params.validate();
  if (!error.empty()) throw std::invalid_argument("network impairment: " + error);
}

void ImpairmentModel::reset() {
  stats_ = {};
  sequence_ = 0;
  bad_state_ = false;
  have_in_order_ = false;
  last_in_order_ns_ = 0;
}

int64_t ImpairmentModel::jitter_ns(uint64_t sequence) const {
  if (params_.jitter_ms <= 0.0) return 0;
  const uint64_t seed = params_.seed;
  double offset_ms = 0.0;
  if (params_.jitter_distribution == JitterDistribution::kUniform) {
    offset_ms = (2.0 * uniform01(seed, sequence, Stream::kJitterA) - 1.0) * params_.jitter_ms;
  } else {
    // Box-Muller; 1 - u keeps the logarithm's argument in (0, 1].
    const double u1 = 1.0 - uniform01(seed, sequence, Stream::kJitterA);
    const double u2 = uniform01(seed, sequence, Stream::kJitterB);
    const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
    offset_ms = std::clamp(z, -4.0, 4.0) * params_.jitter_ms;
  }
  return ms_to_ns(offset_ms);
}

ImpairmentDecision ImpairmentModel::next(int64_t send_time_ns) {
  ImpairmentDecision decision;
  const uint64_t sequence = sequence_++;
  const uint64_t seed = params_.seed;
  decision.sequence = sequence;
  ++stats_.sent;

  if (params_.burst_p_good_to_bad > 0.0) {
    const double u = uniform01(seed, sequence, Stream::kBurstTransition);
    bad_state_ = bad_state_ ? !(u < params_.burst_p_bad_to_good) : (u < params_.burst_p_good_to_bad);
  }
  const bool lost_burst = bad_state_ && uniform01(seed, sequence, Stream::kBurstLoss) < params_.burst_loss_in_bad;
  const bool lost_random = uniform01(seed, sequence, Stream::kLoss) < params_.loss;
  if (lost_burst || lost_random) {
    decision.lost = true;
    decision.lost_in_burst = lost_burst;
    ++stats_.lost;
    ++(lost_burst ? stats_.lost_burst : stats_.lost_random);
    return decision;
  }

  const int64_t delay_ns = std::max<int64_t>(0, ms_to_ns(params_.delay_ms) + jitter_ns(sequence));
  int64_t delivery = send_time_ns + delay_ns;
  if (params_.reorder > 0.0 && uniform01(seed, sequence, Stream::kReorder) < params_.reorder) {
    delivery += ms_to_ns(params_.reorder_delay_ms);  // out of the FIFO: later datagrams may pass it
    decision.reordered = true;
    ++stats_.reordered;
  } else {
    if (have_in_order_) delivery = std::max(delivery, last_in_order_ns_);
    last_in_order_ns_ = delivery;
    have_in_order_ = true;
  }
  decision.delivery_ns[0] = delivery;
  decision.delivery_count = 1;

  if (params_.duplicate > 0.0 && uniform01(seed, sequence, Stream::kDuplicate) < params_.duplicate) {
    const double gap_ms = uniform01(seed, sequence, Stream::kDuplicateGap) * params_.jitter_ms;
    decision.delivery_ns[1] = delivery + ms_to_ns(gap_ms);
    decision.delivery_count = 2;
    decision.duplicated = true;
    ++stats_.duplicated;
  }
  stats_.deliveries += decision.delivery_count;
  return decision;
}

}  // namespace dhr::net
