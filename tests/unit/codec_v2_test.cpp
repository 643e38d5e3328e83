// Visibility codec v2: lossless round trips (intra and against a reference), every shard decodable on its own,
// a wrong or missing reference and corrupted payloads rejected, hostile bytes never written outside a shard's
// rows, the v1 fallback for noise, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <random>

#include "codec/codec.hpp"
#include "codec/codec_v2.hpp"
#include "metrics/visibility_synthetic.hpp"

namespace dhr {
namespace {

// A buffer shifted by (dx, dy) (pixels entering from outside are 0): a reference for motion.
VisibilityBuffer shifted(const VisibilityBuffer& b, int dx, int dy) {
  VisibilityBuffer out = VisibilityBuffer::create(b.width, b.height, b.light_count);
  for (uint32_t y = 0; y < b.height; ++y)
    for (uint32_t x = 0; x < b.width; ++x) {
      const int sx = int(x) - dx, sy = int(y) - dy;
      if (sx >= 0 && sy >= 0 && sx < int(b.width) && sy < int(b.height)) out.set(x, y, b.get(uint32_t(sx), uint32_t(sy)));
    }
  return out;
}

// Decodes every shard into a fresh frame (v2 or v1 payloads); returns the frame, and the error of the first
// shard that failed in out_error.
std::vector<uint8_t> decode_all(const VisibilityBuffer& like, const std::vector<EncodedShard>& shards,
                                const VisibilityBuffer* ref, DecodeError* out_error, uint8_t fill = 0xA5) {
  std::vector<uint8_t> frame(like.data.size(), fill);
  *out_error = DecodeError::kNone;
  for (const EncodedShard& s : shards) {
    const DecodeError e = is_v2_payload(s.payload)
                              ? decode_shard_payload_v2(s.payload, s.first_pixel, s.pixel_count, like.width,
                                                        like.height, like.light_count, ref, frame)
                              : decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, like.mask_bits, frame);
    if (e != DecodeError::kNone && *out_error == DecodeError::kNone) *out_error = e;
  }
  return frame;
}

void expect_shards_tile_rows(const VisibilityBuffer& b, const std::vector<EncodedShard>& shards, size_t max_payload) {
  uint32_t next = 0;
  for (const EncodedShard& s : shards) {
    EXPECT_EQ(s.first_pixel, next);
    EXPECT_LE(s.payload.size(), max_payload);
    EXPECT_FALSE(s.payload.empty());
    next = s.first_pixel + s.pixel_count;
  }
  EXPECT_EQ(next, b.pixel_count());
}

TEST(CodecV2, IntraRoundTripsExactlyForEveryMaskWidth) {
  for (const uint32_t lights : {1u, 3u, 8u, 9u, 17u, 32u}) {
    for (const auto& [w, h] : {std::pair{200u, 120u}, std::pair{67u, 45u}, std::pair{1u, 1u}, std::pair{33u, 9u}}) {
      const VisibilityBuffer b = make_room_visibility(w, h, lights, 7 + lights);
      std::vector<EncodedShard> shards;
      V2Stats stats;
      ASSERT_TRUE(encode_visibility_v2(b, 10, nullptr, EncodeOptions{}, shards, &stats)) << lights << " " << w;
      expect_shards_tile_rows(b, shards, kMaxShardPayload);
      DecodeError e;
      EXPECT_EQ(decode_all(b, shards, nullptr, &e), b.data) << lights << " lights " << w << "x" << h;
      EXPECT_EQ(e, DecodeError::kNone);
      EXPECT_EQ(stats.shards, shards.size());
    }
  }
}

TEST(CodecV2, InterRoundTripsAndIsSmallerThanIntraForAShiftedReference) {
  const VisibilityBuffer b = make_room_visibility(320, 240, 3, 11);
  const VisibilityBuffer ref = shifted(b, 3, -2);
  std::vector<EncodedShard> intra, inter;
  ASSERT_TRUE(encode_visibility_v2(b, 20, nullptr, EncodeOptions{}, intra));
  const V2Reference r{&ref, 17};
  V2Stats stats;
  ASSERT_TRUE(encode_visibility_v2(b, 20, &r, EncodeOptions{}, inter, &stats));
  expect_shards_tile_rows(b, inter, kMaxShardPayload);
  DecodeError e;
  EXPECT_EQ(decode_all(b, inter, &ref, &e), b.data);
  EXPECT_EQ(e, DecodeError::kNone);
  size_t intra_bytes = 0, inter_bytes = 0;
  for (const auto& s : intra) intra_bytes += s.payload.size();
  for (const auto& s : inter) inter_bytes += s.payload.size();
  EXPECT_LT(inter_bytes, intra_bytes);
  EXPECT_GT(stats.blocks_copied, 0u);
  for (const auto& s : inter) EXPECT_EQ(v2_reference_frame(s.payload, 20), std::optional<uint64_t>(17));
}

TEST(CodecV2, EveryShardDecodesOnItsOwn) {
  const VisibilityBuffer b = make_room_visibility(640, 480, 3, 5);
  const VisibilityBuffer ref = make_room_visibility(640, 480, 3, 6);  // another room: much to code
  const V2Reference r{&ref, 1};
  std::vector<EncodedShard> shards;
  ASSERT_TRUE(encode_visibility_v2(b, 2, &r, EncodeOptions{.max_payload = 120}, shards));
  ASSERT_GT(shards.size(), 3u);
  for (size_t keep = 0; keep < shards.size(); ++keep) {
    std::vector<uint8_t> frame(b.data.size(), 0x5A);
    const EncodedShard& s = shards[keep];
    const DecodeError e = is_v2_payload(s.payload)
                              ? decode_shard_payload_v2(s.payload, s.first_pixel, s.pixel_count, b.width, b.height,
                                                        b.light_count, &ref, frame)
                              : decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, b.mask_bits, frame);
    ASSERT_EQ(e, DecodeError::kNone) << "shard " << keep << (is_v2_payload(s.payload) ? " (v2)" : " (v1)");
    const size_t begin = size_t{s.first_pixel} * b.bytes_per_mask(), end = begin + size_t{s.pixel_count} * b.bytes_per_mask();
    EXPECT_TRUE(std::equal(frame.begin() + begin, frame.begin() + end, b.data.begin() + begin)) << "shard " << keep;
    EXPECT_TRUE(std::all_of(frame.begin(), frame.begin() + begin, [](uint8_t v) { return v == 0x5A; }));
    EXPECT_TRUE(std::all_of(frame.begin() + end, frame.end(), [](uint8_t v) { return v == 0x5A; }));
  }
}

// The rows are cut into ranges coded on their own (at multiples of 32 rows); threads code them at once and never
// change a byte.
TEST(CodecV2, RangesCodeOnTheirOwnAndThreadsChangeNoByte) {
  const VisibilityBuffer b = make_room_visibility(640, 480, 3, 5);
  const VisibilityBuffer ref = shifted(b, 3, 1);
  const V2Reference r{&ref, 1};
  for (const V2Reference* reference : {static_cast<const V2Reference*>(nullptr), &r}) {
    std::vector<EncodedShard> one, two, two_on_one, four;
    V2Stats s1, s2;
    ASSERT_TRUE(encode_visibility_v2(b, 2, reference, EncodeOptions{.v2_ranges = 1, .threads = 1}, one, &s1));
    ASSERT_TRUE(encode_visibility_v2(b, 2, reference, EncodeOptions{.v2_ranges = 2, .threads = 2}, two, &s2));
    ASSERT_TRUE(encode_visibility_v2(b, 2, reference, EncodeOptions{.v2_ranges = 2, .threads = 1}, two_on_one));
    ASSERT_TRUE(encode_visibility_v2(b, 2, reference, EncodeOptions{.v2_ranges = 4, .threads = 3}, four));
    ASSERT_EQ(two.size(), two_on_one.size());
    for (size_t i = 0; i < two.size(); ++i) {
      EXPECT_EQ(two[i].first_pixel, two_on_one[i].first_pixel);
      EXPECT_EQ(two[i].payload, two_on_one[i].payload) << "shard " << i;
    }
    // The shards tile the rows once, in order; the second range starts a shard at a 32-row boundary where the
    // single range has none.
    uint32_t next = 0;
    for (const EncodedShard& s : two) {
      EXPECT_EQ(s.first_pixel, next);
      next = s.first_pixel + s.pixel_count;
    }
    EXPECT_EQ(next, b.pixel_count());
    const auto starts_at = [](const std::vector<EncodedShard>& shards, uint32_t pixel) {
      return std::any_of(shards.begin(), shards.end(), [&](const EncodedShard& s) { return s.first_pixel == pixel; });
    };
    bool cut_found = false;
    for (uint32_t y = 32; y < b.height; y += 32)
      cut_found = cut_found || (starts_at(two, y * b.width) && !starts_at(one, y * b.width));
    EXPECT_TRUE(cut_found);
    DecodeError e;
    EXPECT_EQ(decode_all(b, one, &ref, &e), b.data);
    EXPECT_EQ(decode_all(b, two, &ref, &e), b.data);
    EXPECT_EQ(decode_all(b, four, &ref, &e), b.data);
    // A range restarts the models and the block rows: a little more to code, never much.
    EXPECT_LT(s2.payload_bytes, s1.payload_bytes + s1.payload_bytes / 4 + 64);
  }
  // Too few rows for two ranges of 32: one range.
  const VisibilityBuffer small = make_room_visibility(200, 63, 3, 2);
  std::vector<EncodedShard> a, c;
  ASSERT_TRUE(encode_visibility_v2(small, 1, nullptr, EncodeOptions{.v2_ranges = 1}, a));
  ASSERT_TRUE(encode_visibility_v2(small, 1, nullptr, EncodeOptions{.v2_ranges = 8}, c));
  ASSERT_EQ(a.size(), c.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].payload, c[i].payload);
}

TEST(CodecV2, AWrongOrMissingReferenceIsRejectedNotShown) {
  const VisibilityBuffer b = make_room_visibility(160, 120, 3, 3);
  const VisibilityBuffer ref = shifted(b, 2, 0);
  const VisibilityBuffer other = shifted(b, 0, 5);
  const V2Reference r{&ref, 4};
  std::vector<EncodedShard> shards;
  ASSERT_TRUE(encode_visibility_v2(b, 5, &r, EncodeOptions{}, shards));
  DecodeError e;
  decode_all(b, shards, &other, &e);
  EXPECT_EQ(e, DecodeError::kBadPayload);
  decode_all(b, shards, nullptr, &e);
  EXPECT_EQ(e, DecodeError::kBadPayload);
}

TEST(CodecV2, NoiseFallsBackToV1ChunksAndStillRoundTrips) {
  const VisibilityBuffer b = make_random_visibility(300, 40, 8, 99);
  std::vector<EncodedShard> shards;
  V2Stats stats;
  ASSERT_TRUE(encode_visibility_v2(b, 1, nullptr, EncodeOptions{}, shards, &stats));
  EXPECT_GT(stats.v1_fallback_rows, 0u);
  DecodeError e;
  EXPECT_EQ(decode_all(b, shards, nullptr, &e), b.data);
  EXPECT_EQ(e, DecodeError::kNone);
}

TEST(CodecV2, EncodingIsDeterministic) {
  const VisibilityBuffer b = make_room_visibility(256, 128, 5, 8);
  const VisibilityBuffer ref = shifted(b, 1, 1);
  const V2Reference r{&ref, 9};
  std::vector<EncodedShard> a, c;
  ASSERT_TRUE(encode_visibility_v2(b, 10, &r, EncodeOptions{}, a));
  ASSERT_TRUE(encode_visibility_v2(b, 10, &r, EncodeOptions{}, c));
  ASSERT_EQ(a.size(), c.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].payload, c[i].payload);
}

TEST(CodecV2, RejectsInconsistentInput) {
  const VisibilityBuffer b = make_room_visibility(64, 32, 3, 1);
  const VisibilityBuffer small = make_room_visibility(32, 32, 3, 1);
  std::vector<EncodedShard> shards;
  V2Reference r{&small, 1};
  EXPECT_FALSE(encode_visibility_v2(b, 2, &r, EncodeOptions{}, shards));
  r.buffer = &b;
  r.frame_number = 5;
  EXPECT_FALSE(encode_visibility_v2(b, 5, &r, EncodeOptions{}, shards));  // not older
  EXPECT_FALSE(encode_visibility_v2(b, 70000, &r, EncodeOptions{}, shards));  // too old
  VisibilityBuffer broken = b;
  broken.data.pop_back();
  EXPECT_FALSE(encode_visibility_v2(broken, 2, nullptr, EncodeOptions{}, shards));
  EXPECT_TRUE(shards.empty());
}

TEST(CodecV2, HostilePayloadsNeverCrashOrWriteOutsideTheirRows) {
  const VisibilityBuffer b = make_room_visibility(96, 64, 3, 2);
  const VisibilityBuffer ref = shifted(b, 1, 0);
  const V2Reference r{&ref, 1};
  std::vector<EncodedShard> shards;
  ASSERT_TRUE(encode_visibility_v2(b, 2, &r, EncodeOptions{.max_payload = 200}, shards));
  std::mt19937_64 rng(1234);
  for (int trial = 0; trial < 3000; ++trial) {
    const EncodedShard& s = shards[rng() % shards.size()];
    std::vector<uint8_t> p = s.payload;
    switch (trial % 4) {
      case 0: p.resize(rng() % (p.size() + 1)); break;                     // truncated
      case 1: p[rng() % p.size()] ^= uint8_t(1u << (rng() % 8)); break;     // one bit flipped
      case 2: for (auto& v : p) v = uint8_t(rng()); p[0] = trial % 8 < 4 ? kV2TagIntra : kV2TagInter; break;
      default: p.insert(p.end(), rng() % 64, uint8_t(rng())); break;         // trailing garbage
    }
    std::vector<uint8_t> frame(b.data.size(), 0x77);
    (void)decode_shard_payload_v2(p, s.first_pixel, s.pixel_count, b.width, b.height, b.light_count, &ref, frame);
    const size_t begin = size_t{s.first_pixel} * b.bytes_per_mask(), end = begin + size_t{s.pixel_count} * b.bytes_per_mask();
    ASSERT_TRUE(std::all_of(frame.begin(), frame.begin() + begin, [](uint8_t v) { return v == 0x77; }));
    ASSERT_TRUE(std::all_of(frame.begin() + end, frame.end(), [](uint8_t v) { return v == 0x77; }));
  }
  // Geometry that does not fit the frame.
  std::vector<uint8_t> frame(b.data.size());
  const auto& p = shards[0].payload;
  EXPECT_EQ(decode_shard_payload_v2(p, 1, b.width, b.width, b.height, 3, &ref, frame), DecodeError::kBadPayload);
  EXPECT_EQ(decode_shard_payload_v2(p, 0, b.width * (b.height + 1), b.width, b.height, 3, &ref, frame), DecodeError::kBadPayload);
  EXPECT_EQ(decode_shard_payload_v2(p, 0, b.width, b.width, b.height, 33, &ref, frame), DecodeError::kBadPayload);
  EXPECT_EQ(decode_shard_payload_v2(p, 0, b.width, b.width, b.height, 3, &ref, std::span<uint8_t>(frame).first(10)),
            DecodeError::kBadPayload);
}

// Golden bytes: a 16x8 buffer, 3 lights (light 0 lit on the left half, light 1 on the top rows, light 2 on
// a diagonal), intra, one shard. A failure means the bitstream changed: bump kProtocolVersion and say so in
// docs/protocol.md.
TEST(CodecV2, GoldenIntraPayload) {
  VisibilityBuffer b = VisibilityBuffer::create(16, 8, 3);
  for (uint32_t y = 0; y < 8; ++y)
    for (uint32_t x = 0; x < 16; ++x) b.set(x, y, (x < 8 ? 1u : 0u) | (y < 3 ? 2u : 0u) | (x == 2 * y ? 4u : 0u));
  std::vector<EncodedShard> shards;
  ASSERT_TRUE(encode_visibility_v2(b, 1, nullptr, EncodeOptions{}, shards));
  ASSERT_EQ(shards.size(), 1u);
  std::string hex;
  for (uint8_t v : shards[0].payload) {
    char t[4];
    std::snprintf(t, sizeof t, "%02x", v);
    hex += t;
  }
  // tag 0x20 (intra), block rows 0x20, checksum, then the coded bits.
  EXPECT_EQ(hex, "202089524eeee07fbfff0c679bed7d385c958200");
  DecodeError e;
  EXPECT_EQ(decode_all(b, shards, nullptr, &e), b.data);
}

// Golden bytes at every mask width, intra and inter: 96x128 rooms with 3 lights (8-bit masks), 10 (16-bit) and 20
// (32-bit), coded intra and against the same room shifted by (3, -2) with a few pixels changed (so the decider's
// vector search runs); the FNV-1a hash of every shard's payload in order. The band coder's and the decider's loops
// are specialized per mask width; these pin their bytes as the 16x8 golden above pins one intra payload. A failure
// means the bitstream changed: bump kProtocolVersion and say so in docs/protocol.md.
TEST(CodecV2, GoldenPayloadsAtEveryMaskWidth) {
  auto fnv = [](const std::vector<EncodedShard>& shards) {
    uint64_t h = 0xcbf29ce484222325ull;
    for (const EncodedShard& s : shards)
      for (uint8_t v : s.payload) h = (h ^ v) * 0x100000001b3ull;
    return h;
  };
  std::vector<std::string> got;
  for (const uint32_t lights : {3u, 10u, 20u}) {
    const VisibilityBuffer b = make_room_visibility(96, 128, lights, 5);
    VisibilityBuffer ref = shifted(b, 3, -2);
    for (uint32_t i = 0; i < 40; ++i) {
      const uint32_t x = (i * 37) % 96, y = (i * 11) % 128;
      ref.set(x, y, ref.get(x, y) ^ (1u << (i % lights)));
    }
    std::vector<EncodedShard> intra, inter;
    ASSERT_TRUE(encode_visibility_v2(b, 30, nullptr, EncodeOptions{}, intra));
    const V2Reference r{&ref, 29};
    ASSERT_TRUE(encode_visibility_v2(b, 30, &r, EncodeOptions{}, inter));
    EXPECT_GE(intra.size(), 2u) << lights;  // two row ranges: the hash covers more than one shard
    EXPECT_GE(inter.size(), 2u) << lights;
    DecodeError e;
    EXPECT_EQ(decode_all(b, intra, nullptr, &e), b.data) << lights;
    EXPECT_EQ(decode_all(b, inter, &ref, &e), b.data) << lights;
    char text[64];
    std::snprintf(text, sizeof text, "%u: %016llx %016llx", lights, static_cast<unsigned long long>(fnv(intra)),
                  static_cast<unsigned long long>(fnv(inter)));
    got.push_back(text);
  }
  EXPECT_EQ(got, (std::vector<std::string>{"3: 078b67affab3338f a4e8ee7c4d6bd5ad",
                                            "10: 0e81be24386d4c87 69a97753f240fe98",
                                            "20: 4ef0c40b7b8fd593 9ab4dd54ae622ed4"}));
}

}  // namespace
}  // namespace dhr
