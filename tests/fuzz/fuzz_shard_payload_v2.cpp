// Fuzz target: decode_shard_payload_v2 with the rows taken from the first input bytes (bounded, see
// ShardPayloadV2Params), optionally against a fixed reference, and the rest as the payload.
// Properties: no crash or sanitizer report; nothing outside the shard's rows is ever written (accepted or not);
// an invalid geometry is rejected; an accepted payload decodes the same into any frame contents (its checksum
// held) and its rows, re-encoded with v2, decode back unchanged.
#include "codec/codec.hpp"
#include "codec/codec_v2.hpp"
#include "fuzz_layouts.hpp"
#include "fuzz_support.hpp"

#include <algorithm>
#include <vector>

namespace {

constexpr uint8_t kSentinel = 0xA5;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dhr::fuzz::Reader r(data, size);
  const auto p = dhr::fuzz::ShardPayloadV2Params::read(r);
  const std::span<const uint8_t> payload = r.take(r.remaining());
  const uint32_t lights = p.light_count();
  const dhr::VisibilityBuffer ref = dhr::fuzz::v2_fuzz_reference(p.width, p.height, lights);
  const dhr::VisibilityBuffer* reference = (p.mode & 4) ? &ref : nullptr;
  const size_t mb = ref.bytes_per_mask(), row = size_t{p.width} * mb;
  std::vector<uint8_t> frame(ref.data.size(), kSentinel);

  const uint32_t first_pixel = p.first_row * p.width, pixel_count = p.rows * p.width;
  const dhr::DecodeError error = dhr::decode_shard_payload_v2(payload, first_pixel, pixel_count, p.width, p.height,
                                                              lights, reference, frame);
  DHR_FUZZ_CHECK(static_cast<size_t>(error) < dhr::kDecodeErrorCount);
  const bool rows_valid = uint64_t{p.first_row} + p.rows <= p.height;
  if (!rows_valid) {
    DHR_FUZZ_CHECK_MSG(error != dhr::DecodeError::kNone, "rows outside the frame were accepted");
    DHR_FUZZ_CHECK_MSG(std::all_of(frame.begin(), frame.end(), [](uint8_t b) { return b == kSentinel; }),
                       "rows outside the frame were written");
    return 0;
  }
  const size_t begin = p.first_row * row, end = begin + p.rows * row;
  for (size_t i = 0; i < frame.size(); ++i)
    if (i < begin || i >= end) DHR_FUZZ_CHECK_MSG(frame[i] == kSentinel, "written outside the shard's rows");
  if (error != dhr::DecodeError::kNone) return 0;

  std::vector<uint8_t> other(frame.size(), 0);
  DHR_FUZZ_CHECK(dhr::decode_shard_payload_v2(payload, first_pixel, pixel_count, p.width, p.height, lights, reference,
                                              other) == dhr::DecodeError::kNone);
  DHR_FUZZ_CHECK_MSG(std::equal(frame.begin() + static_cast<std::ptrdiff_t>(begin),
                                frame.begin() + static_cast<std::ptrdiff_t>(end),
                                other.begin() + static_cast<std::ptrdiff_t>(begin)),
                     "decoding is not deterministic");

  // The decoded rows as a buffer of their own, through the v2 encoder (intra) and back.
  dhr::VisibilityBuffer rows = dhr::VisibilityBuffer::create(p.width, p.rows, lights);
  std::copy(frame.begin() + static_cast<std::ptrdiff_t>(begin), frame.begin() + static_cast<std::ptrdiff_t>(end),
            rows.data.begin());
  std::vector<dhr::EncodedShard> shards;
  DHR_FUZZ_CHECK(dhr::encode_visibility_v2(rows, 1, nullptr, dhr::EncodeOptions{}, shards));
  std::vector<uint8_t> back(rows.data.size(), kSentinel);
  for (const dhr::EncodedShard& s : shards) {
    const dhr::DecodeError e =
        dhr::is_v2_payload(s.payload)
            ? dhr::decode_shard_payload_v2(s.payload, s.first_pixel, s.pixel_count, p.width, p.rows, lights, nullptr, back)
            : dhr::decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, rows.mask_bits, back);
    DHR_FUZZ_CHECK(e == dhr::DecodeError::kNone);
  }
  DHR_FUZZ_CHECK_MSG(back == rows.data, "re-encoded rows differ");
  return 0;
}
