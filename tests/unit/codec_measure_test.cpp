// Measurement, not an assertion of numbers: compressed bytes per frame for realistic synthetic shadow
// buffers, whole-frame LZ4 against the shardable scheme (the ratio cost of independent shards).
#include "codec/codec.hpp"
#include "metrics/visibility_synthetic.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

namespace dhr {
namespace {

void measure(const char* label, const VisibilityBuffer& b, const EncodeOptions& options) {
  const size_t whole = whole_frame_lz4_size(b.data);
  std::vector<EncodedShard> shards;
  CodecStats stats;
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(encode_visibility(b, options, shards, &stats));
  const auto t1 = std::chrono::steady_clock::now();
  VisibilityBuffer out = VisibilityBuffer::create(b.width, b.height, b.light_count);
  for (const EncodedShard& s : shards)
    ASSERT_EQ(decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, b.mask_bits, out.data), DecodeError::kNone);
  const auto t2 = std::chrono::steady_clock::now();
  ASSERT_EQ(out, b);
  const auto ms = [](auto d) { return std::chrono::duration<double, std::milli>(d).count(); };
  std::printf(
      "{\"case\": \"%s\", \"size\": \"%ux%u\", \"lights\": %u, \"row_aligned\": %s, \"uniform_min_bytes\": %zu, "
      "\"raw_bytes\": %zu, \"whole_frame_lz4\": %zu, \"shard_payload\": %zu, \"shard_datagrams\": %zu, "
      "\"shards\": %zu, \"payload_cost_pct\": %.1f, \"datagram_cost_pct\": %.1f, \"uniform_pixels_pct\": %.1f, "
      "\"chunks\": {\"uniform\": %zu, \"lz4\": %zu, \"raw\": %zu}, \"row_trims\": %zu, "
      "\"encode_ms\": %.2f, \"decode_ms\": %.2f}\n",
      label, b.width, b.height, b.light_count, options.row_aligned ? "true" : "false", options.uniform_min_bytes,
      stats.raw_bytes, whole, stats.payload_bytes, stats.datagram_bytes, stats.shard_count,
      100.0 * (static_cast<double>(stats.payload_bytes) / static_cast<double>(whole) - 1.0),
      100.0 * (static_cast<double>(stats.datagram_bytes) / static_cast<double>(whole) - 1.0),
      100.0 * static_cast<double>(stats.uniform_pixels) / static_cast<double>(b.pixel_count()), stats.uniform_chunks,
      stats.lz4_chunks, stats.raw_chunks, stats.row_trims, ms(t1 - t0), ms(t2 - t1));
}

TEST(CodecMeasure, ShardableVersusWholeFrameLz4) {
  const VisibilityBuffer room = make_room_visibility(1984, 1116, 3, 1);
  const VisibilityBuffer blobs = make_blob_visibility(1984, 1116, 3, 1);
  EncodeOptions options;
  measure("room", room, options);
  measure("blobs", blobs, options);
  // Uniform chunks off (threshold beyond the frame): the pure cost of independently decodable shards.
  for (size_t uniform : {size_t{2048}, size_t{65536}, size_t{1} << 30}) {
    options.uniform_min_bytes = uniform;
    measure("room", room, options);
  }
  options.uniform_min_bytes = size_t{1} << 30;
  measure("blobs", blobs, options);
  options = {};
  options.row_aligned = true;
  measure("room", room, options);
  measure("blobs", blobs, options);
  measure("room_17_lights", make_room_visibility(640, 360, 17, 1), {});
}

}  // namespace
}  // namespace dhr
