// The v2 encoder's block decisions (private to dhr_codec): per block a vector into the reference (searched
// around the previous, the above and the camera-predicted vectors), and per light and 8x8 sub-block whether
// it is uniform, a copy of the displaced reference, or coded pixel by pixel. Decisions only steer the
// encoder; any decision decodes exactly, so they affect size and speed, never correctness.
#pragma once
#include "codec/codec_v2.hpp"
#include "codec_v2_band.hpp"

namespace dhr::codec_detail {

// The decider reads `buffer` and the reference (when given) for the life of the returned function.
BlockDecider make_block_decider(const VisibilityBuffer& buffer, const V2Reference* reference);

}  // namespace dhr::codec_detail
