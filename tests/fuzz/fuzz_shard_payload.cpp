// Fuzz target: decode_shard_payload with the region taken from the first input bytes (bounded, see
// ShardPayloadParams) and the rest as the payload.
// Properties: no crash or sanitizer report; nothing outside the region is ever written (accepted or
// not); the result is deterministic; an accepted payload re-encodes (as a buffer of just that region)
// to shards that decode back to the same masks.
#include "codec/codec.hpp"
#include "fuzz_layouts.hpp"
#include "fuzz_support.hpp"

#include <algorithm>
#include <vector>

namespace {

constexpr uint8_t kSentinel = 0xA5;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dhr::fuzz::Reader r(data, size);
  const auto p = dhr::fuzz::ShardPayloadParams::read(r);
  const std::span<const uint8_t> payload = r.take(r.remaining());

  const uint32_t selector = p.mode & 3u;
  const auto mask_bits = static_cast<dhr::MaskWidth>(selector == 0 ? 8 : selector == 1 ? 16 : selector == 2 ? 32 : 24);
  const size_t mb = selector == 3 ? 3 : dhr::mask_bytes(mask_bits);
  const size_t total = size_t{p.width} * p.height;
  std::vector<uint8_t> frame(total * mb + ((p.mode & 8) ? 1 : 0), kSentinel);

  const dhr::DecodeError error = dhr::decode_shard_payload(payload, p.first_pixel, p.pixel_count, mask_bits, frame);
  DHR_FUZZ_CHECK(static_cast<size_t>(error) < dhr::kDecodeErrorCount);

  // What decode_shard_payload must accept: a whole number of masks in the frame, the region inside it.
  const bool region_valid = selector != 3 && frame.size() % mb == 0 && p.pixel_count > 0 &&
                            uint64_t{p.first_pixel} + p.pixel_count <= frame.size() / mb;
  if (!region_valid) {
    DHR_FUZZ_CHECK_MSG(error != dhr::DecodeError::kNone, "an invalid region was accepted");
    DHR_FUZZ_CHECK_MSG(std::all_of(frame.begin(), frame.end(), [](uint8_t b) { return b == kSentinel; }),
                       "an invalid region was written");
    return 0;
  }
  const size_t begin = size_t{p.first_pixel} * mb, end = begin + size_t{p.pixel_count} * mb;
  for (size_t i = 0; i < frame.size(); ++i)
    if (i < begin || i >= end) DHR_FUZZ_CHECK_MSG(frame[i] == kSentinel, "written outside the region");
  if (error != dhr::DecodeError::kNone) return 0;

  // Accepted: the same input decodes to the same bytes into any frame contents.
  std::vector<uint8_t> other(frame.size(), 0);
  DHR_FUZZ_CHECK(dhr::decode_shard_payload(payload, p.first_pixel, p.pixel_count, mask_bits, other) ==
                 dhr::DecodeError::kNone);
  DHR_FUZZ_CHECK_MSG(std::equal(frame.begin() + static_cast<std::ptrdiff_t>(begin),
                                frame.begin() + static_cast<std::ptrdiff_t>(end),
                                other.begin() + static_cast<std::ptrdiff_t>(begin)),
                     "decoding is not deterministic");

  // The decoded region, as a buffer of some width x height = pixel_count, goes through the encoder
  // and back unchanged (skipped when no such shape fits kMaxBufferDimension, e.g. a large prime).
  uint32_t width = std::min(p.pixel_count, dhr::kMaxBufferDimension);
  while (width > 1 && (p.pixel_count % width != 0 || p.pixel_count / width > dhr::kMaxBufferDimension)) --width;
  if (p.pixel_count / width > dhr::kMaxBufferDimension) return 0;
  dhr::VisibilityBuffer region;
  region.width = width;
  region.height = p.pixel_count / width;
  region.light_count = 32;
  region.mask_bits = mask_bits;
  region.data.assign(frame.begin() + static_cast<std::ptrdiff_t>(begin),
                     frame.begin() + static_cast<std::ptrdiff_t>(end));
  std::vector<dhr::EncodedShard> shards;
  DHR_FUZZ_CHECK(dhr::encode_visibility(region, dhr::EncodeOptions{}, shards));
  std::vector<uint8_t> back(region.data.size(), kSentinel);
  for (const dhr::EncodedShard& s : shards)
    DHR_FUZZ_CHECK(dhr::decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, mask_bits, back) ==
                   dhr::DecodeError::kNone);
  DHR_FUZZ_CHECK_MSG(back == region.data, "re-encoded region differs");
  return 0;
}
