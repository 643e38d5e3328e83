// Fuzz target: the visibility encoder on buffers built from the input (size, light count, options and
// contents from CodecRoundTripParams), through the wire format and the reassembler.
// Properties: encoding succeeds and is deterministic; shards tile the buffer in order; every payload
// fits the (clamped) budget; shard count and total payload stay within codec_bound(); the statistics
// add up; with row_aligned, a shard ends on a row boundary whenever it crosses one; decoding every
// shard restores the buffer exactly; the same shards as datagrams fit kMaxDatagramSize, decode, and
// complete a frame in a VisibilityReassembler that equals the buffer.
#include "codec/codec.hpp"
#include "protocol/protocol.hpp"
#include "codec/reassembly.hpp"
#include "fuzz_layouts.hpp"
#include "fuzz_support.hpp"

#include <algorithm>
#include <vector>

namespace {

using dhr::fuzz::CodecRoundTripParams;

void fill_buffer(const CodecRoundTripParams& p, std::span<const uint8_t> bytes, dhr::VisibilityBuffer& b) {
  const size_t n = b.pixel_count(), mb = b.bytes_per_mask();
  if (bytes.empty()) return;  // all dark
  size_t at = 0;  // cycles through the fill bytes
  auto next = [&]() {
    const uint8_t v = bytes[at];
    at = (at + 1) % bytes.size();
    return v;
  };
  auto next_mask = [&]() {
    uint32_t m = 0;
    for (size_t k = 0; k < mb; ++k) m |= static_cast<uint32_t>(next()) << (8 * k);
    return m;
  };
  switch (p.fill) {
    case CodecRoundTripParams::kRuns:
      for (size_t i = 0; i < n;) {
        const size_t run = 1 + (static_cast<size_t>(next()) | static_cast<size_t>(next()) << 8);
        const uint32_t mask = next_mask();
        for (size_t k = 0; k < run && i < n; ++k, ++i) b.set_mask_at(i, mask);
      }
      break;
    case CodecRoundTripParams::kCyclic:
      for (uint8_t& v : b.data) v = next();
      break;
    case CodecRoundTripParams::kSparse:
      for (size_t i = 0; i < n;) {
        i += next();
        if (i < n) b.set_mask_at(i++, next_mask());
      }
      break;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dhr::fuzz::Reader r(data, size);
  const CodecRoundTripParams p = CodecRoundTripParams::read(r);
  dhr::VisibilityBuffer buffer = dhr::VisibilityBuffer::create(p.width, p.height, p.light_count);
  fill_buffer(p, r.take(r.remaining()), buffer);

  dhr::EncodeOptions options;
  options.max_payload = p.max_payload;
  options.uniform_min_bytes = p.uniform_min_bytes;
  options.row_aligned = p.row_aligned;
  const size_t budget = std::clamp<size_t>(p.max_payload, dhr::kMinShardPayload, dhr::kMaxShardPayload);

  std::vector<dhr::EncodedShard> shards;
  dhr::CodecStats stats;
  DHR_FUZZ_CHECK_MSG(dhr::encode_visibility(buffer, options, shards, &stats), "encoding failed");
  std::vector<dhr::EncodedShard> again;
  DHR_FUZZ_CHECK(dhr::encode_visibility(buffer, options, again));
  DHR_FUZZ_CHECK_MSG(again.size() == shards.size(), "encoding is not deterministic");
  for (size_t i = 0; i < shards.size(); ++i)
    DHR_FUZZ_CHECK_MSG(again[i].payload == shards[i].payload && again[i].first_pixel == shards[i].first_pixel,
                       "encoding is not deterministic");

  const size_t n = buffer.pixel_count();
  const dhr::CodecBound bound = dhr::codec_bound(p.width, p.height, buffer.mask_bits, p.max_payload);
  DHR_FUZZ_CHECK_MSG(!shards.empty() && shards.size() <= bound.max_shards, "shard count above codec_bound");
  size_t next_pixel = 0, payload_total = 0;
  std::vector<uint8_t> decoded(buffer.data.size(), 0xA5);
  for (const dhr::EncodedShard& s : shards) {
    DHR_FUZZ_CHECK_MSG(s.first_pixel == next_pixel && s.pixel_count >= 1, "shards do not tile the buffer");
    DHR_FUZZ_CHECK_MSG(!s.payload.empty() && s.payload.size() <= budget, "payload over budget");
    const size_t end = size_t{s.first_pixel} + s.pixel_count;
    if (p.row_aligned && end < n && end % p.width != 0) {
      const size_t first_boundary = (s.first_pixel / p.width + 1) * size_t{p.width};
      DHR_FUZZ_CHECK_MSG(first_boundary >= end, "row_aligned shard crosses a row boundary but ends mid-row");
    }
    DHR_FUZZ_CHECK_MSG(dhr::decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, buffer.mask_bits,
                                                 decoded) == dhr::DecodeError::kNone,
                       "an encoded shard does not decode");
    next_pixel = end;
    payload_total += s.payload.size();
  }
  DHR_FUZZ_CHECK_MSG(next_pixel == n, "shards do not cover the buffer");
  DHR_FUZZ_CHECK_MSG(payload_total <= bound.max_payload_bytes, "payload bytes above codec_bound");
  DHR_FUZZ_CHECK_MSG(decoded == buffer.data, "decoded buffer differs");
  DHR_FUZZ_CHECK(stats.shard_count == shards.size() && stats.payload_bytes == payload_total);
  DHR_FUZZ_CHECK(stats.raw_bytes == buffer.size_bytes());
  DHR_FUZZ_CHECK(stats.datagram_bytes == payload_total + shards.size() * dhr::kShardFixedSize);
  DHR_FUZZ_CHECK_MSG(stats.uniform_pixels + stats.lz4_pixels + stats.raw_pixels == n, "chunk statistics");

  // Over the wire and into a reassembler.
  dhr::View view;
  view.pose.position = {0.25, 1.6, -0.5};
  const auto messages = dhr::make_visibility_shards(buffer, 7, dhr::Eye::kRight, view, options);
  DHR_FUZZ_CHECK(messages.size() == shards.size());
  dhr::ReassemblerConfig config;
  config.width = p.width;
  config.height = p.height;
  config.light_count = p.light_count;
  config.max_payload = p.max_payload;
  dhr::VisibilityReassembler reassembler(config);
  dhr::InsertStatus last = dhr::InsertStatus::kRejected;
  for (size_t i = 0; i < messages.size(); ++i) {
    const auto bytes = dhr::encode_datagram(dhr::Datagram{42, static_cast<uint32_t>(i), messages[i]});
    DHR_FUZZ_CHECK(!bytes.empty() && bytes.size() <= dhr::kMaxDatagramSize);
    dhr::Datagram d;
    DHR_FUZZ_CHECK_MSG(dhr::decode_datagram(bytes, d) == dhr::DecodeError::kNone, "own shard datagram rejected");
    last = reassembler.insert(std::get<dhr::VisibilityShard>(d.message)).status;
    DHR_FUZZ_CHECK_MSG(last == dhr::InsertStatus::kAccepted || last == dhr::InsertStatus::kCompleted,
                       "reassembler refused a genuine shard");
  }
  DHR_FUZZ_CHECK(last == dhr::InsertStatus::kCompleted);
  const dhr::ReassembledFrame* frame = reassembler.latest_complete(dhr::Eye::kRight);
  DHR_FUZZ_CHECK(frame != nullptr && frame->visibility.frame_number == 7);
  DHR_FUZZ_CHECK_MSG(frame->visibility.buffer.data == buffer.data, "reassembled buffer differs");
  return 0;
}
