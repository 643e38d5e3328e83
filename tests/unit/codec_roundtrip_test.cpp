// Codec round trips over light counts, sizes and content; shard layout invariants; the encode bound.
#include "codec/codec.hpp"
#include "metrics/visibility_synthetic.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>
#include <string>
#include <tuple>

namespace dhr {
namespace {

enum class Pattern { kRandom, kAllLit, kAllDark, kStripes, kBlobs, kRoom };

const char* name(Pattern p) {
  switch (p) {
    case Pattern::kRandom: return "Random";
    case Pattern::kAllLit: return "AllLit";
    case Pattern::kAllDark: return "AllDark";
    case Pattern::kStripes: return "Stripes";
    case Pattern::kBlobs: return "Blobs";
    case Pattern::kRoom: return "Room";
  }
  return "?";
}

VisibilityBuffer make(Pattern p, uint32_t w, uint32_t h, uint32_t lights) {
  switch (p) {
    case Pattern::kRandom: return make_random_visibility(w, h, lights, 42 + lights);
    case Pattern::kAllLit: return make_uniform_visibility(w, h, lights, 0xFFFFFFFFu);
    case Pattern::kAllDark: return make_uniform_visibility(w, h, lights, 0);
    case Pattern::kStripes: return make_stripe_visibility(w, h, lights, 9);
    case Pattern::kBlobs: return make_blob_visibility(w, h, lights, 7 + lights);
    case Pattern::kRoom: return make_room_visibility(w, h, lights, 3);
  }
  return {};
}

// Checks every invariant of an encoding and returns the buffer rebuilt from its shards.
VisibilityBuffer check_and_decode(const VisibilityBuffer& b, const std::vector<EncodedShard>& shards,
                                  const EncodeOptions& options, bool expect_row_aligned) {
  const size_t n = b.pixel_count();
  const size_t budget = std::clamp(options.max_payload, kMinShardPayload, kMaxShardPayload);
  const CodecBound bound = codec_bound(b.width, b.height, b.mask_bits, options.max_payload);
  EXPECT_GE(shards.size(), 1u);
  EXPECT_LE(shards.size(), bound.max_shards);
  size_t next = 0, total = 0;
  VisibilityBuffer out = VisibilityBuffer::create(b.width, b.height, b.light_count);
  for (const EncodedShard& s : shards) {
    EXPECT_EQ(s.first_pixel, next);  // contiguous, in order, no gaps
    EXPECT_GE(s.pixel_count, 1u);
    EXPECT_GE(s.payload.size(), 1u);
    EXPECT_LE(s.payload.size(), budget);
    total += s.payload.size();
    const size_t end = size_t{s.first_pixel} + s.pixel_count;
    if (expect_row_aligned) {
      const bool whole_rows = s.first_pixel % b.width == 0 && (end % b.width == 0 || end == n);
      const bool within_one_row = s.first_pixel / b.width == (end - 1) / b.width;
      const bool ends_on_row = end % b.width == 0 || end == n;  // the rest of a split row, then whole rows
      EXPECT_TRUE(whole_rows || within_one_row || ends_on_row) << "shard [" << s.first_pixel << ", " << end << ")";
    }
    EXPECT_EQ(decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, b.mask_bits, out.data),
              DecodeError::kNone);
    next = end;
  }
  EXPECT_EQ(next, n);
  EXPECT_LE(total, bound.max_payload_bytes);
  return out;
}

using Param = std::tuple<uint32_t, std::pair<uint32_t, uint32_t>, Pattern>;

class CodecRoundTrip : public testing::TestWithParam<Param> {};

TEST_P(CodecRoundTrip, DecodesToTheSameBuffer) {
  const auto [lights, size, pattern] = GetParam();
  const VisibilityBuffer b = make(pattern, size.first, size.second, lights);
  ASSERT_EQ(b.mask_bits, mask_width_for_light_count(lights));
  for (bool aligned : {true, false}) {
    EncodeOptions options;
    options.row_aligned = aligned;
    std::vector<EncodedShard> shards;
    CodecStats stats;
    ASSERT_TRUE(encode_visibility(b, options, shards, &stats));
    EXPECT_EQ(stats.shard_count, shards.size());
    EXPECT_EQ(stats.raw_bytes, b.size_bytes());
    EXPECT_EQ(stats.uniform_pixels + stats.lz4_pixels + stats.raw_pixels, b.pixel_count());
    EXPECT_EQ(stats.datagram_bytes, stats.payload_bytes + shards.size() * kShardFixedSize);
    const VisibilityBuffer out = check_and_decode(b, shards, options, aligned);
    EXPECT_TRUE(out.data == b.data) << name(pattern) << " aligned=" << aligned;
    if (pattern == Pattern::kAllLit || pattern == Pattern::kAllDark) {
      EXPECT_EQ(shards.size(), 1u);  // uniform: one chunk, ~0 bytes
      EXPECT_LE(stats.payload_bytes, 5u + b.bytes_per_mask());
      EXPECT_EQ(stats.uniform_pixels, b.pixel_count());
    }
  }
}

using Size = std::pair<uint32_t, uint32_t>;

std::string param_name(const testing::TestParamInfo<Param>& param_info) {
  const auto& [lights, size, pattern] = param_info.param;
  return std::string(name(pattern)) + "_" + std::to_string(lights) + "lights_" + std::to_string(size.first) + "x" +
         std::to_string(size.second);
}

INSTANTIATE_TEST_SUITE_P(All, CodecRoundTrip,
                         testing::Combine(testing::Values(1u, 3u, 8u, 9u, 16u, 17u, 32u),
                                          testing::Values(Size{1, 1}, Size{7, 5}, Size{160, 120}, Size{1984, 1116}),
                                          testing::Values(Pattern::kRandom, Pattern::kAllLit, Pattern::kAllDark,
                                                          Pattern::kStripes, Pattern::kBlobs)),
                         param_name);
// The toy ray tracer is slow at full size with many lights: full size with few lights only.
INSTANTIATE_TEST_SUITE_P(Room, CodecRoundTrip,
                         testing::Combine(testing::Values(1u, 3u, 8u, 9u, 16u, 17u, 32u),
                                          testing::Values(Size{1, 1}, Size{7, 5}, Size{160, 120}),
                                          testing::Values(Pattern::kRoom)),
                         param_name);
INSTANTIATE_TEST_SUITE_P(RoomFullSize, CodecRoundTrip,
                         testing::Combine(testing::Values(1u, 3u), testing::Values(Size{1984, 1116}),
                                          testing::Values(Pattern::kRoom)),
                         param_name);

TEST(Codec, SmallBudgetsAndThresholdsStillRoundTrip) {
  const VisibilityBuffer b = make_blob_visibility(333, 97, 17, 11);
  const VisibilityBuffer r = make_random_visibility(61, 43, 9, 3);
  for (size_t budget : {size_t{1}, size_t{64}, size_t{100}, size_t{257}, size_t{600}, kMaxShardPayload, size_t{5000}})
    for (size_t uniform : {size_t{0}, size_t{32}, size_t{300}, size_t{100000}})
      for (const VisibilityBuffer* buf : {&b, &r})
        for (bool aligned : {false, true}) {
          SCOPED_TRACE("budget " + std::to_string(budget) + " uniform " + std::to_string(uniform) + " buffer " +
                       std::to_string(buf->width) + " aligned " + std::to_string(aligned));
          EncodeOptions options;
          options.max_payload = budget;
          options.uniform_min_bytes = uniform;
          options.row_aligned = aligned;
          std::vector<EncodedShard> shards;
          ASSERT_TRUE(encode_visibility(*buf, options, shards));
          EXPECT_TRUE(check_and_decode(*buf, shards, options, aligned).data == buf->data);
        }
}

TEST(Codec, EachShardDecodesOnItsOwn) {
  const VisibilityBuffer b = make_room_visibility(640, 360, 3, 9);
  std::vector<EncodedShard> shards;
  ASSERT_TRUE(encode_visibility(b, {}, shards));
  ASSERT_GT(shards.size(), 2u);
  for (const EncodedShard& s : shards) {
    VisibilityBuffer out = VisibilityBuffer::create(b.width, b.height, b.light_count);
    std::fill(out.data.begin(), out.data.end(), uint8_t{0xEE});  // sentinel outside the region
    ASSERT_EQ(decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, b.mask_bits, out.data),
              DecodeError::kNone);
    for (size_t i = 0; i < b.pixel_count(); ++i) {
      const bool inside = i >= s.first_pixel && i < size_t{s.first_pixel} + s.pixel_count;
      ASSERT_EQ(out.data[i], inside ? b.data[i] : 0xEE) << "pixel " << i;
    }
  }
}

TEST(Codec, UniformRunsCostAlmostNothing) {
  // Top half dark, bottom half shadow-like: the dark half must be one uniform chunk.
  VisibilityBuffer b = make_blob_visibility(1984, 1116, 3, 1);
  const size_t half = b.pixel_count() / 2;
  for (size_t i = 0; i < half; ++i) b.set_mask_at(i, 0);
  std::vector<EncodedShard> shards;
  CodecStats stats;
  ASSERT_TRUE(encode_visibility(b, {}, shards, &stats));
  EXPECT_GE(stats.uniform_pixels, half);
  EXPECT_LE(shards.front().payload.size(), kMaxShardPayload);
  EXPECT_GE(shards.front().pixel_count, half);
}

TEST(Codec, WorstCaseStaysWithinTheBound) {
  for (uint32_t lights : {8u, 16u, 32u}) {
    const VisibilityBuffer b = make_random_visibility(4096, 64, lights, 5);
    std::vector<EncodedShard> shards;
    CodecStats stats;
    ASSERT_TRUE(encode_visibility(b, {}, shards, &stats));
    const CodecBound bound = codec_bound(b.width, b.height, b.mask_bits);
    EXPECT_LE(shards.size(), bound.max_shards);
    EXPECT_LE(stats.payload_bytes, bound.max_payload_bytes);
    EXPECT_GT(stats.raw_pixels, 0u);  // random 8-bit masks do not compress: stored raw
    EXPECT_TRUE(check_and_decode(b, shards, {}, false).data == b.data);
  }
  // The largest frame the protocol allows, incompressible, fits the 16-bit shard index.
  const CodecBound largest = codec_bound(kMaxBufferDimension, kMaxBufferDimension, MaskWidth::k32);
  EXPECT_LE(largest.max_shards, 65535u);
}

TEST(Codec, RejectsInconsistentBuffers) {
  std::vector<EncodedShard> shards;
  VisibilityBuffer b = make_uniform_visibility(10, 10, 3, 1);
  b.data.pop_back();
  EXPECT_FALSE(encode_visibility(b, {}, shards));
  EXPECT_TRUE(shards.empty());
  VisibilityBuffer empty;
  EXPECT_FALSE(encode_visibility(empty, {}, shards));
  VisibilityBuffer wide = make_uniform_visibility(10, 10, 3, 1);
  wide.width = kMaxBufferDimension + 1;
  EXPECT_FALSE(encode_visibility(wide, {}, shards));
  EXPECT_TRUE(make_visibility_shards(b, 1, Eye::kLeft, View{}).empty());
}

TEST(Codec, IsDeterministic) {
  const VisibilityBuffer b = make_room_visibility(320, 200, 5, 2);
  std::vector<EncodedShard> a, c;
  ASSERT_TRUE(encode_visibility(b, {}, a));
  ASSERT_TRUE(encode_visibility(b, {}, c));
  ASSERT_EQ(a.size(), c.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].first_pixel, c[i].first_pixel);
    EXPECT_EQ(a[i].payload, c[i].payload);
  }
  EXPECT_EQ(make_room_visibility(320, 200, 5, 2), b);
}

TEST(Codec, GoldenUniformAndRawPayloads) {
  // Uniform: kind 0, count 35, mask 0x0105 (16-bit masks, 9 lights).
  const VisibilityBuffer u = make_uniform_visibility(7, 5, 9, 0x0105);
  std::vector<EncodedShard> shards;
  ASSERT_TRUE(encode_visibility(u, {}, shards));
  ASSERT_EQ(shards.size(), 1u);
  EXPECT_EQ(shards[0].payload, (std::vector<uint8_t>{0x00, 0x23, 0x00, 0x00, 0x00, 0x05, 0x01}));
  // Hand-written payload: raw 2 pixels, uniform 3 pixels, into 8-bit masks.
  const std::vector<uint8_t> payload = {0x02, 0x02, 0x00, 0x00, 0x00, 0xAA, 0xBB,  // raw
                                        0x00, 0x03, 0x00, 0x00, 0x00, 0x07};       // uniform
  std::vector<uint8_t> frame(6, 0x11);
  ASSERT_EQ(decode_shard_payload(payload, 1, 5, MaskWidth::k8, frame), DecodeError::kNone);
  EXPECT_EQ(frame, (std::vector<uint8_t>{0x11, 0xAA, 0xBB, 0x07, 0x07, 0x07}));
}

TEST(Codec, MakeVisibilityShardsFillsTheMessages) {
  const VisibilityBuffer b = make_blob_visibility(640, 480, 3, 4);
  View view;
  view.pose.position = {1, 2, 3};
  const auto shards = make_visibility_shards(b, 77, Eye::kRight, view);
  ASSERT_GT(shards.size(), 1u);
  VisibilityBuffer out = VisibilityBuffer::create(b.width, b.height, b.light_count);
  for (size_t i = 0; i < shards.size(); ++i) {
    const VisibilityShard& s = shards[i];
    EXPECT_EQ(s.frame_number, 77u);
    EXPECT_EQ(s.eye, Eye::kRight);
    EXPECT_EQ(s.shard_index, i);
    EXPECT_EQ(s.shard_count, shards.size());
    EXPECT_EQ(s.buffer_width, 640);
    EXPECT_EQ(s.buffer_height, 480);
    EXPECT_EQ(s.view.pose.position, view.pose.position);
    EXPECT_LE(encoded_size(Message{s}), kMaxDatagramSize);
    ASSERT_EQ(decode_shard_payload(s.payload_bytes(), s.first_pixel, s.pixel_count, s.mask_bits, out.data),
              DecodeError::kNone);
  }
  EXPECT_EQ(out, b);
}

TEST(VisibilityBufferWidth, ConvertsBetweenMaskWidthsWithoutChangingAMask) {
  VisibilityBuffer b = VisibilityBuffer::create(7, 5, 6);
  ASSERT_EQ(b.mask_bits, MaskWidth::k8);
  for (size_t p = 0; p < b.pixel_count(); ++p) b.set_mask_at(p, static_cast<uint32_t>(p * 37u) & b.light_bits());
  for (const MaskWidth w : {MaskWidth::k8, MaskWidth::k16, MaskWidth::k32}) {
    const VisibilityBuffer c = b.with_mask_width(w);
    EXPECT_EQ(c.mask_bits, w);
    EXPECT_EQ(c.data.size(), b.pixel_count() * mask_bytes(w));
    for (size_t p = 0; p < b.pixel_count(); ++p) ASSERT_EQ(c.mask_at(p), b.mask_at(p));
    EXPECT_EQ(c.with_mask_width(MaskWidth::k8), b);
  }
  const VisibilityBuffer many = VisibilityBuffer::create(2, 2, 12);
  EXPECT_THROW((void)many.with_mask_width(MaskWidth::k8), std::invalid_argument);
  EXPECT_NO_THROW((void)many.with_mask_width(MaskWidth::k32));
}

}  // namespace
}  // namespace dhr
