// VisibilityTracer::trace_layout on the project's area-light scene (assets/scenes/default_room_area.gltf: a rect
// light, a punctual light and a sphere light): hard fields are the hard tracer's bits, soft fields the Gray code of
// quantize(trace_soft_image's fraction), a hard layout is trace_lights bit for bit, the result does not depend on the
// thread count, and the interface's default (for tracers that know only hard bits) agrees with the sampled fields
// wherever the sampled fraction is 0 or 1, up to a measured bound. The Vulkan backend samples as Embree does: its
// bound is tests/vulkan/vulkan_tracer_soft_layout_test.cpp's.
#include "trace/embree/embree_tracer.hpp"
#include "trace/soft/soft_image.hpp"
#include "trace/stats_json.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace dhr::server {
namespace {

constexpr const char* kAreaScene = "assets/scenes/default_room_area.gltf";

struct AreaScene {
  Scene scene;
  std::vector<Camera> cameras;
};

const AreaScene& area_scene() {
  static const AreaScene* s = [] {
    auto* out = new AreaScene;
    out->scene = test::load_scene_or_fail(test::source_path(kAreaScene));
    out->cameras = test::bookmark_cameras(test::source_path(kAreaScene), Extent{160, 120});
    return out;
  }();
  return *s;
}

TracerOptions two_threads() {
  TracerOptions o;
  o.threads = 2;
  return o;
}

// A wrapper that implements only trace() and trace_lights(), with the light extents: trace_layout is then the
// interface's default (the centre ray widened to level 0 or 7), which wrappers that know only hard bits get.
class DefaultLayoutTracer final : public VisibilityTracer {
 public:
  explicit DefaultLayoutTracer(VisibilityTracer& inner) : inner_(inner) {}
  TracerBackend backend() const override { return inner_.backend(); }
  std::string device_description() const override { return inner_.device_description(); }
  const AccelStats& accel_stats() const override { return inner_.accel_stats(); }
  uint32_t light_count() const override { return inner_.light_count(); }
  std::vector<bool> light_extents() const override { return inner_.light_extents(); }
  void trace(const Camera& camera, VisibilityBuffer& out, TraceStats& out_stats) override {
    inner_.trace(camera, out, out_stats);
  }
  void trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out, TraceStats& out_stats) override {
    inner_.trace_lights(camera, lights, out, out_stats);
  }

 private:
  VisibilityTracer& inner_;
};

TEST(SoftLayoutTrace, SceneHasSoftAndHardLights) {
  const AreaScene& s = area_scene();
  ASSERT_FALSE(s.cameras.empty());
  EmbreeTracer tracer(s.scene, two_threads());
  const VisibilityLayout layout = layout_for_lights(tracer.light_extents(), tracer.light_count());
  ASSERT_TRUE(layout.any_soft());
  uint32_t soft = 0;
  for (uint32_t i = 0; i < layout.light_count; ++i) soft += layout.is_soft(i) ? 1u : 0u;
  EXPECT_GE(soft, 2u);                   // the rect and the sphere light
  EXPECT_LT(soft, layout.light_count);   // and a punctual one
  EXPECT_EQ(layout.total_bits(), layout.light_count + soft * (kSoftLevelBits - 1));
}

TEST(SoftLayoutTrace, HardFieldsAreTheHardBitsAndSoftFieldsTheQuantizedSoftImage) {
  const AreaScene& s = area_scene();
  EmbreeTracer tracer(s.scene, two_threads());
  const uint32_t n = tracer.light_count();
  const VisibilityLayout layout = layout_for_lights(tracer.light_extents(), n);
  uint64_t soft_pairs = 0, fractional = 0;
  for (const Camera& camera : s.cameras) {
    VisibilityBuffer fields, hard;
    TraceStats fs, hs;
    tracer.trace_layout(camera, layout, fields, fs);
    tracer.trace_lights(camera, n, hard, hs);  // every light traced to its centre: today's bits
    SoftImage soft;
    SoftImageOptions so;
    so.threads = 2;
    const SoftStats ss = trace_soft_image(tracer.embree_scene(), s.scene.lights, camera, so, soft);
    ASSERT_EQ(fields.light_count, layout.total_bits());
    ASSERT_EQ(fields.mask_bits, layout.mask_width());
    size_t hard_mismatch = 0, soft_mismatch = 0, stray_bits = 0;
    uint64_t soft_rays = 0;
    for (uint32_t y = 0; y < camera.extent.height; ++y) {
      for (uint32_t x = 0; x < camera.extent.width; ++x) {
        const uint32_t mask = fields.get(x, y);
        if (mask & ~layout.used_bits()) ++stray_bits;
        for (uint32_t l = 0; l < n; ++l) {
          const size_t i = soft.index(x, y, l);
          if (layout.is_soft(l)) {
            if (gray_decode(layout.field(mask, l)) != quantize(soft.fraction[i], kDefaultSoftLevels)) ++soft_mismatch;
            soft_rays += soft.rays[i];
            if (soft.fraction[i] > 0.0f && soft.fraction[i] < 1.0f) ++fractional;
          } else if (layout.field(mask, l) != ((hard.get(x, y) >> l) & 1u)) {
            ++hard_mismatch;
          }
        }
      }
    }
    EXPECT_EQ(hard_mismatch, 0u);
    EXPECT_EQ(soft_mismatch, 0u);
    EXPECT_EQ(stray_bits, 0u);
    EXPECT_EQ(fs.soft_shadow_rays, soft_rays);  // the same samples, ray for ray
    EXPECT_EQ(fs.pixels, hs.pixels);
    EXPECT_EQ(fs.background_pixels, hs.background_pixels);
    EXPECT_EQ(fs.primary_rays, hs.primary_rays);
    EXPECT_LE(fs.soft_refined_pairs, ss.refined_pairs);
    soft_pairs += fs.soft_pairs;
    std::printf("[ soft layout ] %s\n", to_json(fs).dump().c_str());
  }
  EXPECT_GT(soft_pairs, 0u);
  EXPECT_GT(fractional, 0u);  // there are penumbrae: the levels are not just the hard bits
}

TEST(SoftLayoutTrace, HardLayoutIsTraceLightsBitForBit) {
  const AreaScene& s = area_scene();
  EmbreeTracer tracer(s.scene, two_threads());
  for (const Camera& camera : s.cameras) {
    for (uint32_t n : {tracer.light_count(), 1u}) {
      VisibilityBuffer a, b;
      TraceStats sa, sb;
      tracer.trace_layout(camera, VisibilityLayout::hard(n), a, sa);
      tracer.trace_lights(camera, n, b, sb);
      EXPECT_TRUE(a == b);
      EXPECT_EQ(sa.shadow_rays, sb.shadow_rays);
      EXPECT_EQ(sa.soft_pairs, 0u);
    }
  }
}

TEST(SoftLayoutTrace, DeterministicForAnyThreadCountAndRun) {
  const AreaScene& s = area_scene();
  TracerOptions one;
  one.threads = 1;
  EmbreeTracer a(s.scene, one), b(s.scene, two_threads());
  const VisibilityLayout layout = layout_for_lights(a.light_extents(), a.light_count());
  const Camera& camera = s.cameras.front();
  VisibilityBuffer va, vb, vb2;
  TraceStats sa, sb, sb2;
  a.trace_layout(camera, layout, va, sa);
  b.trace_layout(camera, layout, vb, sb);
  b.trace_layout(camera, layout, vb2, sb2);
  EXPECT_TRUE(va == vb);
  EXPECT_TRUE(vb == vb2);
  EXPECT_EQ(sa.soft_shadow_rays, sb.soft_shadow_rays);
  EXPECT_EQ(sa.soft_refined_pairs, sb.soft_refined_pairs);
}

TEST(SoftLayoutTrace, SubsetLayoutTracesOnlyItsLights) {
  const AreaScene& s = area_scene();
  EmbreeTracer tracer(s.scene, two_threads());
  const std::vector<bool> extents = tracer.light_extents();
  const uint32_t n = tracer.light_count();
  const VisibilityLayout full = layout_for_lights(extents, n);
  const Camera& camera = s.cameras.front();
  VisibilityBuffer all;
  TraceStats st;
  tracer.trace_layout(camera, full, all, st);
  for (uint32_t k = 1; k < n; ++k) {
    const VisibilityLayout sub = layout_for_lights(extents, k);
    VisibilityBuffer part;
    tracer.trace_layout(camera, sub, part, st);
    ASSERT_EQ(part.light_count, sub.total_bits());
    EXPECT_EQ(st.lights_unrequested, n - k);
    // The first k fields are the same bits (the layout places them the same way).
    size_t differ = 0;
    for (size_t p = 0; p < all.pixel_count(); ++p) differ += (all.mask_at(p) & sub.used_bits()) != part.mask_at(p);
    EXPECT_EQ(differ, 0u) << k;
  }
  EXPECT_THROW(tracer.trace_layout(camera, VisibilityLayout::hard(n + 1), all, st), std::invalid_argument);
}

// Skips change no field: a sphere light whose range cannot reach the view is culled as a whole (its field is 0,
// no ray), and the same fields come out with every skip off (SkipOptions::none()), hard and soft.
TEST(SoftLayoutTrace, SkipsAndCullingTakeASoftFieldAsAWhole) {
  Scene scene = test::make_empty_scene();
  test::add_grid(scene, {-10, 0, 10}, {20, 0, 0}, {0, 0, -20}, 4, test::kSingleSided);
  test::add_box(scene, {-0.5f, 0.5f, -0.5f}, {0.5f, 1.5f, 0.5f}, test::kSingleSided);
  SceneLight near = test::point_light({1.0f, 3.5f, 0.5f}, 10.0f);
  near.radius = 0.4f;
  SceneLight far = test::point_light({0.0f, 3.0f, 60.0f}, 10.0f, /*range=*/5.0f);  // behind the camera
  far.radius = 0.5f;
  scene.lights = {near, test::point_light({-1.0f, 3.0f, 0.0f}, 10.0f), far};
  test::finalize(scene);
  const Camera camera = test::look_camera({0.0, 5.0, 6.0}, {0.0, 0.0, 0.0}, 96, 72);
  TracerOptions skipping = two_threads(), exhaustive = two_threads();
  exhaustive.skip = SkipOptions::none();
  EmbreeTracer a(scene, skipping), b(scene, exhaustive);
  const VisibilityLayout layout = layout_for_lights(a.light_extents(), a.light_count());
  ASSERT_TRUE(layout.is_soft(0) && !layout.is_soft(1) && layout.is_soft(2));
  VisibilityBuffer va, vb;
  TraceStats sa, sb;
  a.trace_layout(camera, layout, va, sa);
  b.trace_layout(camera, layout, vb, sb);
  EXPECT_TRUE(va == vb);
  EXPECT_EQ(sa.lights_culled, 1u);
  EXPECT_EQ(sb.lights_culled, 0u);
  const uint64_t hits = sa.pixels - sa.background_pixels;
  EXPECT_EQ(sa.soft_pairs, hits);       // the near sphere only
  EXPECT_EQ(sb.soft_pairs, 2 * hits);   // both: the far one's test at its centre says out of range, no ray
  EXPECT_EQ(sa.soft_shadow_rays, sb.soft_shadow_rays);
  EXPECT_LT(sa.shadow_rays, sb.shadow_rays);  // the hard light's skipped pairs
  size_t far_set = 0, near_set = 0;
  for (size_t p = 0; p < va.pixel_count(); ++p) {
    far_set += layout.field(va.mask_at(p), 2) != 0;
    near_set += layout.field(va.mask_at(p), 0) != 0;
  }
  EXPECT_EQ(far_set, 0u);
  EXPECT_GT(near_set, 0u);
}

// The interface's default trace_layout (the ray to the centre, level 0 or 7) has the
// same hard fields, and its soft fields equal the sampled ones where the sampled fraction is 0 or 1, except where
// the centre ray and the samples disagree (an occluder edge between the centre and the samples). Measured below.
TEST(SoftLayoutTrace, DefaultLayoutIsTheCentreRayWidenedAndAgreesWhereSamplingIsUniform) {
  const AreaScene& s = area_scene();
  EmbreeTracer tracer(s.scene, two_threads());
  DefaultLayoutTracer interim(tracer);
  const uint32_t n = tracer.light_count();
  const VisibilityLayout layout = layout_for_lights(tracer.light_extents(), n);
  uint64_t uniform = 0, disagree = 0;
  for (const Camera& camera : s.cameras) {
    VisibilityBuffer sampled, centre, hard;
    TraceStats st;
    tracer.trace_layout(camera, layout, sampled, st);
    interim.trace_layout(camera, layout, centre, st);
    tracer.trace_lights(camera, n, hard, st);
    SoftImage soft;
    SoftImageOptions so;
    so.threads = 2;
    trace_soft_image(tracer.embree_scene(), s.scene.lights, camera, so, soft);
    ASSERT_EQ(centre.light_count, layout.total_bits());
    for (uint32_t y = 0; y < camera.extent.height; ++y) {
      for (uint32_t x = 0; x < camera.extent.width; ++x) {
        const uint32_t cm = centre.get(x, y), sm = sampled.get(x, y), bit_mask = hard.get(x, y);
        for (uint32_t l = 0; l < n; ++l) {
          const uint32_t bit = (bit_mask >> l) & 1u;
          if (!layout.is_soft(l)) {
            ASSERT_EQ(layout.field(cm, l), bit);
            ASSERT_EQ(layout.field(sm, l), bit);
            continue;
          }
          const uint32_t c = gray_decode(layout.field(cm, l));
          ASSERT_EQ(c, bit ? kDefaultSoftLevels - 1 : 0u);  // the centre ray, widened
          const size_t i = soft.index(x, y, l);
          // Pairs the sampler took samples for, whose samples all agreed (fraction exactly 0 or 1).
          if (soft.rays[i] == 0 || (soft.fraction[i] != 0.0f && soft.fraction[i] != 1.0f)) continue;
          ++uniform;
          if (gray_decode(layout.field(sm, l)) != c) ++disagree;
        }
      }
    }
  }
  ASSERT_GT(uniform, 0u);
  const double share = static_cast<double>(disagree) / static_cast<double>(uniform);
  std::printf("[ interim ] %llu of %llu sampled soft pairs with fraction 0 or 1 differ from the centre ray (%.4f %%)\n",
              static_cast<unsigned long long>(disagree), static_cast<unsigned long long>(uniform), 100.0 * share);
  EXPECT_LT(share, 0.01);
}

}  // namespace
}  // namespace dhr::server
