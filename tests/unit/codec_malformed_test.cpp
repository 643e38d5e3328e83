// The payload decoder rejects malformed, truncated and inconsistent chunks and never writes outside
// its region, whatever the bytes.
#include "codec/codec.hpp"
#include "metrics/visibility_synthetic.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace dhr {
namespace {

using Bytes = std::vector<uint8_t>;

struct Sample {
  VisibilityBuffer buffer;
  std::vector<EncodedShard> shards;
};

Sample sample(uint32_t lights) {
  Sample s{make_room_visibility(128, 72, lights, 4), {}};
  EncodeOptions options;
  options.max_payload = 400;  // several shards, mixed chunk kinds
  options.uniform_min_bytes = 256;
  EXPECT_TRUE(encode_visibility(s.buffer, options, s.shards));
  EXPECT_GT(s.shards.size(), 2u);
  return s;
}

// Decodes into a frame filled with a sentinel and checks nothing outside the region changed.
DecodeError decode_guarded(const Bytes& payload, const EncodedShard& shard, const VisibilityBuffer& b) {
  std::vector<uint8_t> frame(b.size_bytes(), 0x5A);
  const DecodeError e = decode_shard_payload(payload, shard.first_pixel, shard.pixel_count, b.mask_bits, frame);
  const size_t mb = b.bytes_per_mask();
  const auto untouched = [](auto first, auto last) {
    return std::all_of(first, last, [](uint8_t v) { return v == 0x5A; });
  };
  const auto begin = frame.begin() + static_cast<std::ptrdiff_t>(size_t{shard.first_pixel} * mb);
  const auto end = begin + static_cast<std::ptrdiff_t>(size_t{shard.pixel_count} * mb);
  EXPECT_TRUE(untouched(frame.begin(), begin) && untouched(end, frame.end())) << "write outside the region";
  return e;
}

TEST(CodecMalformed, EveryTruncationIsRejected) {
  for (uint32_t lights : {3u, 12u, 20u}) {
    const Sample s = sample(lights);
    for (const EncodedShard& shard : s.shards) {
      for (size_t n = 0; n < shard.payload.size(); ++n) {
        const Bytes prefix(shard.payload.begin(), shard.payload.begin() + static_cast<std::ptrdiff_t>(n));
        EXPECT_EQ(decode_guarded(prefix, shard, s.buffer), DecodeError::kBadPayload) << "prefix " << n;
      }
    }
  }
}

TEST(CodecMalformed, TrailingBytesAreRejected) {
  const Sample s = sample(3);
  Bytes p = s.shards[0].payload;
  p.push_back(0);
  EXPECT_EQ(decode_guarded(p, s.shards[0], s.buffer), DecodeError::kBadPayload);
}

TEST(CodecMalformed, ChunkHeadersAreChecked) {
  const VisibilityBuffer b = make_uniform_visibility(8, 2, 3, 0);
  const EncodedShard region{0, 16, {}};
  // Count larger than the region.
  EXPECT_EQ(decode_guarded({0x00, 0x11, 0x00, 0x00, 0x00, 0x01}, region, b), DecodeError::kBadPayload);
  // Count zero.
  EXPECT_EQ(decode_guarded({0x00, 0x00, 0x00, 0x00, 0x00, 0x01}, region, b), DecodeError::kBadPayload);
  // Count that would overflow 32 bits when added.
  EXPECT_EQ(decode_guarded({0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0x01}, region, b), DecodeError::kBadPayload);
  // Unknown kind.
  EXPECT_EQ(decode_guarded({0x03, 0x10, 0x00, 0x00, 0x00, 0x01}, region, b), DecodeError::kBadPayload);
  // Covers fewer pixels than the region.
  EXPECT_EQ(decode_guarded({0x00, 0x0F, 0x00, 0x00, 0x00, 0x01}, region, b), DecodeError::kBadPayload);
  // Raw chunk with too few bytes.
  EXPECT_EQ(decode_guarded({0x02, 0x10, 0x00, 0x00, 0x00, 0x01, 0x02}, region, b), DecodeError::kBadPayload);
  // LZ4 chunk of size 0, and of a size beyond the payload.
  EXPECT_EQ(decode_guarded({0x01, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00}, region, b), DecodeError::kBadPayload);
  EXPECT_EQ(decode_guarded({0x01, 0x10, 0x00, 0x00, 0x00, 0x40, 0x00, 0x10, 0x00}, region, b),
            DecodeError::kBadPayload);
  // Empty payload.
  EXPECT_EQ(decode_guarded({}, region, b), DecodeError::kBadPayload);
  // Two valid chunks exactly covering the region are fine.
  EXPECT_EQ(decode_guarded({0x00, 0x08, 0x00, 0x00, 0x00, 0x01, 0x00, 0x08, 0x00, 0x00, 0x00, 0x02}, region, b),
            DecodeError::kNone);
}

TEST(CodecMalformed, Lz4BlockMustDecompressToExactlyItsCount) {
  const Sample s = sample(3);
  // Find an LZ4 chunk at the start of some shard and change its pixel count by +-1.
  bool tested = false;
  for (const EncodedShard& shard : s.shards) {
    if (shard.payload[0] != static_cast<uint8_t>(ChunkKind::kLz4)) continue;
    for (int delta : {-1, +1}) {
      Bytes p = shard.payload;
      uint32_t count = p[1] | p[2] << 8 | p[3] << 16 | static_cast<uint32_t>(p[4]) << 24;
      count = static_cast<uint32_t>(static_cast<int64_t>(count) + delta);
      for (int i = 0; i < 4; ++i) p[1 + i] = static_cast<uint8_t>(count >> (8 * i));
      EncodedShard widened = shard;
      widened.pixel_count = static_cast<uint32_t>(static_cast<int64_t>(shard.pixel_count) + delta);
      EXPECT_EQ(decode_guarded(p, widened, s.buffer), DecodeError::kBadPayload) << "delta " << delta;
    }
    tested = true;
    break;
  }
  EXPECT_TRUE(tested) << "no shard starts with an LZ4 chunk";
}

TEST(CodecMalformed, RegionAndMaskWidthAreChecked) {
  const std::vector<uint8_t> payload = {0x00, 0x04, 0x00, 0x00, 0x00, 0x01};
  std::vector<uint8_t> frame(8);
  EXPECT_EQ(decode_shard_payload(payload, 5, 4, MaskWidth::k8, frame), DecodeError::kBadValue);  // past the end
  EXPECT_EQ(decode_shard_payload(payload, 0, 0, MaskWidth::k8, frame), DecodeError::kBadValue);
  EXPECT_EQ(decode_shard_payload(payload, UINT32_MAX, 4, MaskWidth::k8, frame), DecodeError::kBadValue);
  EXPECT_EQ(decode_shard_payload(payload, 0, 4, static_cast<MaskWidth>(24), frame), DecodeError::kBadValue);
  std::vector<uint8_t> odd(7);
  EXPECT_EQ(decode_shard_payload(payload, 0, 1, MaskWidth::k16, odd), DecodeError::kBadValue);
  EXPECT_EQ(decode_shard_payload(payload, 4, 4, MaskWidth::k8, frame), DecodeError::kNone);
}

TEST(CodecMalformed, RandomCorruptionNeverWritesOutsideOrCrashes) {
  uint64_t state = 99;
  auto next = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint32_t>(state >> 33);
  };
  size_t rejected = 0, total = 0;
  for (uint32_t lights : {3u, 12u, 20u}) {
    const Sample s = sample(lights);
    for (const EncodedShard& shard : s.shards) {
      for (int iter = 0; iter < 300; ++iter) {
        Bytes p = shard.payload;
        const int flips = 1 + static_cast<int>(next() % 3);
        for (int f = 0; f < flips; ++f) p[next() % p.size()] ^= static_cast<uint8_t>(1u << (next() % 8));
        if (next() % 5 == 0) p.resize(next() % (p.size() + 1));
        ++total;
        if (decode_guarded(p, shard, s.buffer) != DecodeError::kNone) ++rejected;
      }
    }
  }
  EXPECT_GT(rejected, total / 4);  // most corruptions hit structure; flips inside data may decode
}

TEST(CodecMalformed, GarbagePayloadsNeverCrash) {
  uint64_t state = 4242;
  std::vector<uint8_t> frame(64 * 64 * 4);
  for (int iter = 0; iter < 20000; ++iter) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    Bytes p(static_cast<size_t>(state >> 53));  // 0..2047 bytes
    for (auto& x : p) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      x = static_cast<uint8_t>(state >> 56);
    }
    if (!p.empty()) p[0] = static_cast<uint8_t>(iter % 3);  // valid kinds, so chunk bodies are exercised
    const auto width = iter % 3 == 0 ? MaskWidth::k8 : iter % 3 == 1 ? MaskWidth::k16 : MaskWidth::k32;
    const uint32_t px = static_cast<uint32_t>(frame.size() / mask_bytes(width));
    (void)decode_shard_payload(p, static_cast<uint32_t>(state % 16), px - 16, width, frame);
  }
  SUCCEED();
}

}  // namespace
}  // namespace dhr
