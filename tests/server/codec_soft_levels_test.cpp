// The codecs on masks with soft-level fields (Gray-coded levels of default_room_area's rect and sphere lights,
// traced by the Embree tracer's trace_layout): lossless intra and inter round trips through codec v2 and v1 at
// mask widths 8, 16 and 32 (the wider ones stack the real fields of the scene's lights into more fields), every
// shard decodable on its own, and the bytes per frame printed next to the hard layout's (measured, not asserted).
#include "scene/camera_bookmarks.hpp"
#include "codec/codec.hpp"
#include "codec/codec_v2.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

namespace dhr::server {
namespace {

constexpr const char* kAreaScene = "assets/scenes/default_room_area.gltf";
constexpr Extent kEye{320, 240};

struct Traced {
  VisibilityLayout layout;
  std::vector<std::array<VisibilityBuffer, 2>> soft;  // per bookmark: the pose, then the pose moved 2 cm
  std::vector<std::array<VisibilityBuffer, 2>> hard;
};

const Traced& traced() {
  static const Traced* t = [] {
    auto* out = new Traced;
    const Scene scene = test::load_scene_or_fail(test::source_path(kAreaScene));
    TracerOptions options;
    options.threads = 2;
    EmbreeTracer tracer(scene, options);
    out->layout = layout_for_lights(tracer.light_extents(), tracer.light_count());
    std::string error;
    const auto bookmarks = load_camera_bookmarks(camera_bookmarks_path(test::source_path(kAreaScene)), &error);
    EXPECT_TRUE(bookmarks) << error;
    if (!bookmarks) return out;
    for (const CameraBookmark& b : *bookmarks) {
      std::array<VisibilityBuffer, 2> soft, hard;
      for (int moved = 0; moved < 2; ++moved) {
        Pose pose = left_eye_pose(look_at_pose(b).value());
        pose.position.x += 0.02 * moved;
        const Camera camera = Camera::with_guard_band(View{pose, symmetric_fov(90.0, kEye)}, kEye, GuardBand{});
        TraceStats stats;
        tracer.trace_layout(camera, out->layout, soft[moved], stats);
        tracer.trace_lights(camera, tracer.light_count(), hard[moved], stats);
      }
      out->soft.push_back(std::move(soft));
      out->hard.push_back(std::move(hard));
    }
    return out;
  }();
  return *t;
}

// `fields` soft fields (and `hard_lights` hard bits after them), field k the real field of the scene's soft light
// k % (soft lights), moved k pixels right: the real levels' statistics at a wider mask.
VisibilityBuffer widen(const VisibilityBuffer& real, const VisibilityLayout& real_layout, uint32_t fields,
                       uint32_t hard_lights, VisibilityLayout& out_layout) {
  std::vector<uint32_t> soft_lights;
  for (uint32_t i = 0; i < real_layout.light_count; ++i)
    if (real_layout.is_soft(i)) soft_lights.push_back(i);
  bool soft[kMaxLights] = {};
  for (uint32_t k = 0; k < fields; ++k) soft[k] = true;
  out_layout = VisibilityLayout::for_lights(std::span<const bool>(soft, fields + hard_lights));
  VisibilityBuffer out = VisibilityBuffer::create(real.width, real.height, out_layout.total_bits());
  for (uint32_t y = 0; y < real.height; ++y)
    for (uint32_t x = 0; x < real.width; ++x) {
      uint32_t m = 0;
      for (uint32_t k = 0; k < fields + hard_lights; ++k) {
        const uint32_t sx = x >= k ? x - k : 0;
        const uint32_t src = real.get(sx, y);
        const uint32_t light = k < fields ? soft_lights[k % soft_lights.size()] : 0;
        m = out_layout.with_visibility(m, k, real_layout.visibility(src, light));
      }
      out.set(x, y, m);
    }
  return out;
}

std::vector<uint8_t> decode_all(const VisibilityBuffer& like, const std::vector<EncodedShard>& shards,
                                const VisibilityBuffer* ref) {
  std::vector<uint8_t> frame(like.data.size(), 0xA5);
  for (const EncodedShard& s : shards) {
    const DecodeError e = is_v2_payload(s.payload)
                              ? decode_shard_payload_v2(s.payload, s.first_pixel, s.pixel_count, like.width,
                                                        like.height, like.light_count, ref, frame)
                              : decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, like.mask_bits, frame);
    EXPECT_EQ(e, DecodeError::kNone);
  }
  return frame;
}

size_t payload_bytes(const std::vector<EncodedShard>& shards) {
  size_t n = 0;
  for (const EncodedShard& s : shards) n += s.payload.size();
  return n;
}

// Intra and inter (against the unmoved pose) round trips, and each inter shard alone; returns the bytes.
std::array<size_t, 3> round_trip(const VisibilityBuffer& ref, const VisibilityBuffer& cur, const char* what) {
  std::vector<EncodedShard> intra, inter, v1;
  EXPECT_TRUE(encode_visibility_v2(cur, 2, nullptr, EncodeOptions{}, intra)) << what;
  EXPECT_EQ(decode_all(cur, intra, nullptr), cur.data) << what << " intra";
  const V2Reference r{&ref, 1};
  EXPECT_TRUE(encode_visibility_v2(cur, 2, &r, EncodeOptions{.max_payload = 400}, inter)) << what;
  EXPECT_EQ(decode_all(cur, inter, &ref), cur.data) << what << " inter";
  for (size_t keep = 0; keep < inter.size(); ++keep) {
    std::vector<uint8_t> frame(cur.data.size(), 0x5A);
    const EncodedShard& s = inter[keep];
    const DecodeError e = is_v2_payload(s.payload)
                              ? decode_shard_payload_v2(s.payload, s.first_pixel, s.pixel_count, cur.width,
                                                        cur.height, cur.light_count, &ref, frame)
                              : decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, cur.mask_bits, frame);
    EXPECT_EQ(e, DecodeError::kNone) << what << " shard " << keep;
    const size_t begin = size_t{s.first_pixel} * cur.bytes_per_mask();
    const size_t end = begin + size_t{s.pixel_count} * cur.bytes_per_mask();
    EXPECT_TRUE(std::equal(frame.begin() + begin, frame.begin() + end, cur.data.begin() + begin)) << what << keep;
    EXPECT_TRUE(std::all_of(frame.begin(), frame.begin() + begin, [](uint8_t v) { return v == 0x5A; }));
    EXPECT_TRUE(std::all_of(frame.begin() + end, frame.end(), [](uint8_t v) { return v == 0x5A; }));
  }
  EXPECT_TRUE(encode_visibility(cur, EncodeOptions{}, v1)) << what;
  EXPECT_EQ(decode_all(cur, v1, nullptr), cur.data) << what << " v1";
  return {payload_bytes(intra), payload_bytes(inter), payload_bytes(v1)};
}

TEST(CodecSoftLevels, RealSoftLevelsRoundTripAtEveryMaskWidth) {
  const Traced& t = traced();
  ASSERT_FALSE(t.soft.empty());
  ASSERT_TRUE(t.layout.any_soft());
  ASSERT_EQ(t.soft[0][0].mask_bits, MaskWidth::k8);
  for (size_t i = 0; i < t.soft.size(); ++i) {
    const auto soft = round_trip(t.soft[i][0], t.soft[i][1], "soft 8-bit");
    const auto hard = round_trip(t.hard[i][0], t.hard[i][1], "hard");
    std::printf("[ soft levels ] bookmark %zu %ux%u, %u bits (hard %u): v2 intra %zu B (hard %zu), v2 inter %zu B "
                "(hard %zu), v1 %zu B (hard %zu)\n",
                i, kEye.width, kEye.height, t.layout.total_bits(), t.layout.light_count, soft[0], hard[0], soft[1],
                hard[1], soft[2], hard[2]);
  }
  for (const auto& [fields, hard_lights, width] :
       {std::tuple{5u, 0u, MaskWidth::k16}, std::tuple{4u, 4u, MaskWidth::k16}, std::tuple{10u, 2u, MaskWidth::k32},
        std::tuple{8u, 8u, MaskWidth::k32}}) {
    VisibilityLayout layout;
    const VisibilityBuffer ref = widen(t.soft[0][0], t.layout, fields, hard_lights, layout);
    const VisibilityBuffer cur = widen(t.soft[0][1], t.layout, fields, hard_lights, layout);
    ASSERT_EQ(cur.mask_bits, width) << fields;
    ASSERT_EQ(layout.demoted, 0u);
    const auto bytes = round_trip(ref, cur, width == MaskWidth::k16 ? "soft 16-bit" : "soft 32-bit");
    std::printf("[ soft levels ] %u level fields + %u bits = %u bits: v2 intra %zu B, inter %zu B, v1 %zu B\n",
                fields, hard_lights, layout.total_bits(), bytes[0], bytes[1], bytes[2]);
  }
}

}  // namespace
}  // namespace dhr::server
