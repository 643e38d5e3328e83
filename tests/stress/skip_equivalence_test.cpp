// Every skip against the exhaustive path, identical output bits:
//  - tracer (Embree, and Vulkan on lavapipe): each SkipOptions flag alone, and all, vs SkipOptions::none(),
//    on the default room, the real scenes when present, and a hand-made scene that exercises every skip;
//  - codec: uniform chunks on vs off, and masks as narrow as the light count vs 32-bit masks: identical
//    decoded masks;
//  - client (when built): the prediction pass's visibility upload key (an upload skipped for an unchanged
//    buffer) vs uploading every frame: identical images (client_skip_equivalence_test.cpp).
#include "codec/codec.hpp"
#include "stress_support.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace dhr::stress {
namespace {

using server::SkipOptions;
using server::TracerBackend;

struct SkipCase {
  const char* name;
  SkipOptions skip;
};

std::vector<SkipCase> skip_cases() {
  SkipOptions backfacing = SkipOptions::none(), range = SkipOptions::none(), cull = SkipOptions::none();
  backfacing.backfacing = true;
  range.out_of_range = true;
  cull.cull_lights = true;
  return {{"backfacing", backfacing}, {"out_of_range", range}, {"cull_lights", cull}, {"all", SkipOptions{}}};
}

// Cameras around the scene's bounds (scenes without a bookmark file).
std::vector<Camera> orbit_cameras(const Scene& scene, Extent eye, int count) {
  std::vector<Camera> out;
  const glm::dvec3 c(scene.bounds.center());
  const double r = std::max(0.5, double(scene.bounds.diagonal()));
  for (int i = 0; i < count; ++i) {
    const double a = 0.6 + 2.0 * glm::pi<double>() * i / count;
    out.push_back(test::look_camera(c + glm::dvec3(r * std::sin(a), 0.4 * r, r * std::cos(a)), c, eye.width,
                                    eye.height, 60.0));
  }
  return out;
}

// Floor, a box, and lights that make every skip fire: a spot (cone), a range-limited point light, a light
// below the floor (back-facing for every floor pixel) and a short-range light behind the camera (culled).
Scene all_skips_scene() {
  Scene scene = test::make_empty_scene();
  test::add_grid(scene, {-6, 0, 6}, {12, 0, 0}, {0, 0, -12}, 6, test::kSingleSided);
  test::add_box(scene, {-1, 0, -1}, {1, 1.5f, 1}, test::kSingleSided);
  scene.lights = {test::point_light({0.5f, 4.0f, 2.0f}, 20.0f),
                  test::spot_light({-2.0f, 3.0f, -1.0f}, {0.3f, -1.0f, 0.4f}, 10.0f, 25.0f),
                  test::point_light({2.5f, 1.0f, 2.5f}, 5.0f, 2.0f),
                  test::point_light({0.0f, -2.0f, 0.0f}, 5.0f),
                  test::point_light({0.0f, 2.0f, 30.0f}, 5.0f, 1.0f)};
  test::finalize(scene);
  return scene;
}

struct Totals {
  uint64_t differing = 0;
  uint64_t bits = 0;
  server::TraceStats skipping;  // summed counters of the skipping runs
};

Totals compare(TracerBackend backend, const Scene& scene, const std::vector<Camera>& cameras, SkipOptions skip) {
  const server::TracerOptions on = backend == TracerBackend::kEmbree ? embree_options(skip) : vulkan_options(skip);
  const server::TracerOptions off =
      backend == TracerBackend::kEmbree ? embree_options(SkipOptions::none()) : vulkan_options(SkipOptions::none());
  auto skipping = server::create_tracer(backend, scene, on);
  auto exhaustive = server::create_tracer(backend, scene, off);
  Totals t;
  for (const Camera& c : cameras) {
    VisibilityBuffer a, b;
    server::TraceStats sa, sb;
    skipping->trace(c, a, sa);
    exhaustive->trace(c, b, sb);
    t.differing += differing_bits(a, b);
    t.bits += total_bits(b);
    const uint64_t pairs = (sa.pixels - sa.background_pixels) * scene.lights.size();
    EXPECT_EQ(sb.shadow_rays, pairs);
    EXPECT_EQ(sa.shadow_rays + sa.skipped_backfacing + sa.skipped_out_of_range + sa.skipped_culled_light, pairs);
    if (!skip.backfacing) {
      EXPECT_EQ(sa.skipped_backfacing, 0u);
    }
    if (!skip.out_of_range) {
      EXPECT_EQ(sa.skipped_out_of_range, 0u);
    }
    if (!skip.cull_lights) {
      EXPECT_EQ(sa.skipped_culled_light, 0u);
    }
    t.skipping.shadow_rays += sa.shadow_rays;
    t.skipping.skipped_backfacing += sa.skipped_backfacing;
    t.skipping.skipped_out_of_range += sa.skipped_out_of_range;
    t.skipping.skipped_culled_light += sa.skipped_culled_light;
  }
  return t;
}

void expect_every_skip_changes_nothing(TracerBackend backend, const char* scene_name, const Scene& scene,
                                       const std::vector<Camera>& cameras, bool require_each_skip) {
  ASSERT_FALSE(cameras.empty());
  uint64_t differing = 0;
  for (const SkipCase& c : skip_cases()) {
    const Totals t = compare(backend, scene, cameras, c.skip);
    EXPECT_EQ(t.differing, 0u) << scene_name << " " << c.name;
    differing += t.differing;
    if (require_each_skip) {  // the skip really fired, so the comparison means something
      if (c.skip.backfacing) {
        EXPECT_GT(t.skipping.skipped_backfacing, 0u) << c.name;
      }
      if (c.skip.out_of_range) {
        EXPECT_GT(t.skipping.skipped_out_of_range, 0u) << c.name;
      }
      if (c.skip.cull_lights) {
        EXPECT_GT(t.skipping.skipped_culled_light, 0u) << c.name;
      }
    }
  }
  report(std::string("skip_tracer_") + backend_label(backend) + "_" + scene_name, "differing_bits", double(differing),
         0.0);
}

TEST(SkipEquivalence, EmbreeEverySkipOnTheHandMadeScene) {
  const Scene scene = all_skips_scene();
  const std::vector<Camera> cameras = {test::look_camera({0.0, 4.0, 7.0}, {0.0, 0.0, 0.0}, 96, 72, 80.0),
                                       test::look_camera({-4.0, 2.0, -5.0}, {0.5, 0.5, 0.5}, 96, 72, 70.0)};
  expect_every_skip_changes_nothing(TracerBackend::kEmbree, "hand_made", scene, cameras, true);
}

TEST(SkipEquivalence, VulkanEverySkipOnTheHandMadeScene) {
  const Scene scene = all_skips_scene();
  const std::vector<Camera> cameras = {test::look_camera({0.0, 4.0, 7.0}, {0.0, 0.0, 0.0}, 40, 30, 80.0)};
  expect_every_skip_changes_nothing(TracerBackend::kVulkan, "hand_made", scene, cameras, true);
}

TEST(SkipEquivalence, EmbreeEverySkipOnTheDefaultRoom) {
  const std::string path = test::source_path(kDefaultScenePath);
  expect_every_skip_changes_nothing(TracerBackend::kEmbree, "default_room", load_scene_or_fail(path),
                                    bookmark_cameras(path, pick(Extent{64, 48}, Extent{192, 144})), false);
}

TEST(SkipEquivalence, VulkanEverySkipOnTheDefaultRoom) {
  const std::string path = test::source_path(kDefaultScenePath);
  std::vector<Camera> cameras = bookmark_cameras(path, pick(Extent{32, 24}, Extent{96, 72}));
  if (!long_mode() && cameras.size() > 2) cameras.resize(2);
  expect_every_skip_changes_nothing(TracerBackend::kVulkan, "default_room", load_scene_or_fail(path), cameras, false);
}

TEST(SkipEquivalence, EmbreeEverySkipOnTheRealScenes) {
  const std::string living = test::shared_data_path("scenes/living_room.glb");
  if (living.empty()) GTEST_SKIP() << "../shared/data not present: real scenes skipped";
  expect_every_skip_changes_nothing(TracerBackend::kEmbree, "living_room", load_scene_or_fail(living),
                                    bookmark_cameras(living, pick(Extent{64, 48}, Extent{192, 144})), false);
  const Scene lamp = load_scene_or_fail(test::shared_data_path("scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf"));
  expect_every_skip_changes_nothing(TracerBackend::kEmbree, "lights_punctual_lamp", lamp,
                                    orbit_cameras(lamp, pick(Extent{64, 48}, Extent{192, 144}), 4), false);
}

TEST(SkipEquivalence, VulkanAllSkipsOnTheRealScenes) {
  const std::string living = test::shared_data_path("scenes/living_room.glb");
  if (living.empty()) GTEST_SKIP() << "../shared/data not present: real scenes skipped";
  const Scene lamp = load_scene_or_fail(test::shared_data_path("scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf"));
  const Totals t = compare(TracerBackend::kVulkan, lamp, orbit_cameras(lamp, Extent{32, 24}, 2), SkipOptions{});
  EXPECT_EQ(t.differing, 0u);
  std::vector<Camera> cameras = bookmark_cameras(living, Extent{32, 24});
  if (!long_mode() && cameras.size() > 1) cameras.resize(1);
  const Totals u = compare(TracerBackend::kVulkan, load_scene_or_fail(living), cameras, SkipOptions{});
  EXPECT_EQ(u.differing, 0u);
  report("skip_tracer_vulkan_real_scenes", "differing_bits", double(t.differing + u.differing), 0.0);
}

// --- Codec ----------------------------------------------------------------------------------------------

// Decodes every shard into a buffer of the given layout; false on any decode error.
bool decode_all(const std::vector<EncodedShard>& shards, VisibilityBuffer& out) {
  for (const EncodedShard& s : shards) {
    if (decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, out.mask_bits, out.data) != DecodeError::kNone)
      return false;
  }
  return true;
}

std::vector<VisibilityBuffer> codec_inputs() {
  std::vector<VisibilityBuffer> out;
  const std::string path = test::source_path(kDefaultScenePath);
  const Scene room = load_scene_or_fail(path);
  for (const Camera& c : bookmark_cameras(path, pick(Extent{128, 96}, Extent{640, 480})))
    out.push_back(trace_once(TracerBackend::kEmbree, room, c));
  const Scene hand = all_skips_scene();
  out.push_back(trace_once(TracerBackend::kEmbree, hand, test::look_camera({0.0, 4.0, 7.0}, {0, 0, 0}, 200, 150)));
  // Edge cases: all dark, all lit, 17 lights (16-bit -> 32-bit masks), a one-pixel buffer.
  VisibilityBuffer dark = VisibilityBuffer::create(300, 7, 3), lit = dark, many = VisibilityBuffer::create(64, 40, 17);
  for (size_t i = 0; i < lit.pixel_count(); ++i) lit.set_mask_at(i, lit.light_bits());
  for (size_t i = 0; i < many.pixel_count(); ++i) many.set_mask_at(i, (i / 97 % 3 == 0) ? many.light_bits() : uint32_t(i * 2654435761u) & many.light_bits());
  VisibilityBuffer one = VisibilityBuffer::create(1, 1, 1);
  one.set_mask_at(0, 1);
  out.insert(out.end(), {dark, lit, many, one});
  return out;
}

TEST(SkipEquivalence, CodecUniformChunksAndNarrowMasksDecodeToTheSameBits) {
  EncodeOptions with_uniform;  // defaults: uniform chunks for long runs
  EncodeOptions without_uniform;
  without_uniform.uniform_min_bytes = std::numeric_limits<size_t>::max();  // never a uniform chunk
  size_t differing = 0, bytes_skip = 0, bytes_full = 0, uniform_chunks = 0;
  for (const VisibilityBuffer& v : codec_inputs()) {
    const VisibilityBuffer wide = v.with_mask_width(MaskWidth::k32);
    std::vector<EncodedShard> a, b, c;
    CodecStats sa, sb, sc;
    ASSERT_TRUE(encode_visibility(v, with_uniform, a, &sa));
    ASSERT_TRUE(encode_visibility(v, without_uniform, b, &sb));
    ASSERT_TRUE(encode_visibility(wide, without_uniform, c, &sc));
    // Off means off, except that a buffer of one single mask is always one uniform chunk (codec.cpp).
    bool single_mask = true;
    for (size_t i = 1; i < v.pixel_count() && single_mask; ++i) single_mask = v.mask_at(i) == v.mask_at(0);
    EXPECT_EQ(sb.uniform_chunks, single_mask ? 1u : 0u) << v.width << "x" << v.height << " " << v.light_count;
    EXPECT_EQ(sc.uniform_chunks, single_mask ? 1u : 0u) << v.width << "x" << v.height << " " << v.light_count;
    uniform_chunks += sa.uniform_chunks;
    VisibilityBuffer da = v, db = v, dc = wide;
    std::fill(da.data.begin(), da.data.end(), 0xA5);  // garbage: every byte must be overwritten
    std::fill(db.data.begin(), db.data.end(), 0x5A);
    std::fill(dc.data.begin(), dc.data.end(), 0x3C);
    ASSERT_TRUE(decode_all(a, da) && decode_all(b, db) && decode_all(c, dc));
    EXPECT_TRUE(da == v);
    EXPECT_TRUE(db == v);
    for (size_t i = 0; i < v.pixel_count(); ++i) differing += (dc.mask_at(i) != v.mask_at(i)) + (da.mask_at(i) != db.mask_at(i));
    bytes_skip += sa.datagram_bytes;
    bytes_full += sc.datagram_bytes;
  }
  EXPECT_GT(uniform_chunks, 0u) << "the inputs must exercise uniform chunks";
  report("skip_codec", "differing_masks", double(differing), 0.0);
  std::printf("[stress] skip_codec: %zu bytes with skips vs %zu bytes (no uniform chunks, 32-bit masks)\n", bytes_skip,
              bytes_full);
  EXPECT_EQ(differing, 0u);
  EXPECT_LT(bytes_skip, bytes_full);
}

}  // namespace
}  // namespace dhr::stress
