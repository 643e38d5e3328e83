// How dhr-eval's ground truth samples a light with an extent (eval_truth.hpp), apart so RunOptions can hold it.
#pragma once
#include <cstdint>

namespace dhr::eval {

// Samples per pixel and light with an extent, SoftOptions{kTruthFirstSamples, kTruthSamples}: the first ones, a
// stratified net over the light, decide where the point sees all of it or none (the umbrae and the fully lit);
// where they disagree (the penumbrae) all kTruthSamples are taken. Doubling either moves visibility_error by less
// than 1 % (docs/evaluation.md, "Soft shadows"). A punctual light takes one ray (the hard tracer's bit).
inline constexpr uint32_t kTruthFirstSamples = 32;
inline constexpr uint32_t kTruthSamples = 256;
// The scramble: one per pixel (SoftPattern::kPerPixel, unbiased noise rather than the server's banding) with its
// own salt, independent of the server's (salt 0), so the truth's noise does not agree with what it judges.
inline constexpr uint32_t kTruthSalt = 0x74727574u;

struct TruthSampling {
  uint32_t first_samples = kTruthFirstSamples;  // equal to samples: uniform sampling
  uint32_t samples = kTruthSamples;
  uint32_t salt = kTruthSalt;
  uint32_t threads = 0;  // 0: all cores
};

}  // namespace dhr::eval
