// The v2 band coder's adaptive models (private to dhr_codec): their context sizes, the region state a mode's
// context reads, and the models a shard starts from (codec_v2_band.hpp codes with them).
#pragma once
#include "range_coder.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dhr::codec_detail {

inline constexpr uint32_t kIntraContextBits = 9;
inline constexpr uint32_t kInterContextBits = 9;
inline constexpr uint32_t kVectorMagnitudeContexts = 16;

// What the decoder already knows of one light around the region a mode covers (BandCoder::code_block): all 0,
// all 1, both, or nothing. Inter, the reference under the region displaced by a vector it knows (the block's
// predictor for block modes, the block's vector for sub-block modes); intra, the 8 rows above. The mode contexts
// read it: a region the reference shows uniform is mostly uniform again, with the same value. On the area room
// (992x558, 30 frames of Gul User1, 50 ms) it took the inter frames' block and sub-block modes from 1,220 to 606
// bytes per eye frame (each decoded bit's -log2 p summed in an instrumented decoder).
inline constexpr uint32_t kRefStates = 4;
inline constexpr uint8_t kRefAllZero = 0, kRefAllOne = 1, kRefMixed = 2, kRefNone = 3;
inline uint8_t ref_state(uint32_t any, uint32_t all, uint32_t light) {
  return ((any >> light) & 1u) == 0 ? kRefAllZero : ((all >> light) & 1u) != 0 ? kRefAllOne : kRefMixed;
}

// Adaptive models, reset at every shard's start.
struct Models {
  // Mode models are shared by all lights: with the reference state in the context, a context per light (tried: the
  // first three lights apart, the rest together) codes 1.6 % more bytes on the area room (992x558, 30 frames).
  Probability coded[2][2][kRefStates][2];  // [sub-block level][inter][reference state][left neighbour coded]
  Probability copy[2][kRefStates];      // [level][reference state]: copy vs uniform (inter)
  Probability value[2][2][kRefStates][2];  // [level][inter][reference state][previous uniform value]
  Probability vec_zero[2];
  Probability vec_sign[2];
  Probability vec_magnitude[2][kVectorMagnitudeContexts];
  Probability vec_escape[9];
  std::vector<Probability> intra = std::vector<Probability>(size_t{1} << kIntraContextBits);
  std::vector<Probability> inter = std::vector<Probability>(size_t{1} << kInterContextBits);

  void reset() {
    Probability* groups[] = {&coded[0][0][0][0], &copy[0][0], &value[0][0][0][0], vec_zero, vec_sign,
                             &vec_magnitude[0][0], vec_escape};
    const size_t counts[] = {sizeof coded, sizeof copy, sizeof value, sizeof vec_zero, sizeof vec_sign,
                             sizeof vec_magnitude, sizeof vec_escape};
    for (size_t g = 0; g < 7; ++g) std::fill_n(groups[g], counts[g] / sizeof(Probability), Probability{});
    std::fill(intra.begin(), intra.end(), Probability{});
    std::fill(inter.begin(), inter.end(), Probability{});
  }
};

}  // namespace dhr::codec_detail
