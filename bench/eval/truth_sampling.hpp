// How dhr-eval's ground truth samples a light with an extent (eval_truth.hpp), apart so RunOptions can hold it.
#pragma once
#include <cstdint>

namespace dhr::eval {

// Uniform samples per light with an extent: doubling them moves visibility_error by less than 1 %
// (docs/evaluation.md, "Soft shadows"). A punctual light takes one ray (the hard tracer's bit) whatever this says.
inline constexpr uint32_t kTruthSamples = 256;
// The scramble's salt: independent of the server's (SoftOptions::salt 0), so the truth's noise does not agree
// with what it judges.
inline constexpr uint32_t kTruthSalt = 0x74727574u;

struct TruthSampling {
  uint32_t samples = kTruthSamples;
  uint32_t salt = kTruthSalt;
  uint32_t threads = 0;  // 0: all cores
};

}  // namespace dhr::eval
