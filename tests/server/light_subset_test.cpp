// VisibilityTracer::trace_lights: a client asking for the first N of the scene's lights gets exactly the bits
// the full trace gives those lights, and the other lights cost no light test and no ray (Embree backend here,
// tests/vulkan/vulkan_tracer_test.cpp for Vulkan). Also the interface's default for wrapper tracers.
#include "trace/embree/embree_tracer.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>

namespace dhr::server {
namespace {

using test::add_box;
using test::add_grid;
using test::finalize;

// Nine lights (16-bit masks for all of them, 8-bit for a subset of up to 8), every kind, some culled.
Scene nine_light_scene() {
  Scene scene = test::make_empty_scene();
  add_grid(scene, {-10, 0, 10}, {20, 0, 0}, {0, 0, -20}, 8, test::kSingleSided);
  add_box(scene, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f}, test::kSingleSided);
  add_box(scene, {1.0f, 0.0f, -2.0f}, {2.0f, 2.0f, -1.0f}, test::kDoubleSided);
  scene.lights = {
      test::point_light({0.0f, 2.5f, 0.0f}, 10.0f),
      test::point_light({-2.0f, 1.5f, 1.0f}, 10.0f, 3.0f),
      test::directional_light({0.3f, -1.0f, 0.2f}),
      test::spot_light({2.0f, 3.0f, 1.0f}, {-0.3f, -1.0f, -0.2f}, 15.0f, 30.0f),
      test::point_light({0.0f, 1.0f, 9.0f}, 10.0f, 2.0f),  // behind the camera, small range: culled
      test::point_light({3.0f, 0.5f, -3.0f}, 10.0f),
      test::directional_light({-0.5f, -1.0f, 0.0f}),
      test::point_light({-3.0f, 4.0f, -4.0f}, 10.0f, 8.0f),
      test::point_light({0.5f, 0.2f, 1.5f}, 10.0f),  // grazing the floor
  };
  finalize(scene);
  return scene;
}

TracerOptions options_with(SkipOptions skip) {
  TracerOptions o;
  o.skip = skip;
  o.threads = 2;
  return o;
}

// Bits of lights [0, n) of `full` equal `subset`'s, pixel by pixel.
void expect_subset_bits(const VisibilityBuffer& full, const VisibilityBuffer& subset, uint32_t n) {
  ASSERT_EQ(subset.width, full.width);
  ASSERT_EQ(subset.height, full.height);
  ASSERT_EQ(subset.light_count, n);
  EXPECT_EQ(subset.mask_bits, mask_width_for_light_count(n));
  uint64_t differing = 0, lit = 0;
  for (size_t i = 0; i < full.pixel_count(); ++i) {
    differing += subset.mask_at(i) != (full.mask_at(i) & subset.light_bits());
    lit += subset.mask_at(i) != 0;
  }
  EXPECT_EQ(differing, 0u) << n << " lights";
  if (n > 0) {
    EXPECT_GT(lit, 0u) << n << " lights";
  }
}

TEST(LightSubset, EmbreeSubsetHasTheFullTracesBitsAndNoRaysForTheOthers) {
  const Scene scene = nine_light_scene();
  const uint32_t total = static_cast<uint32_t>(scene.lights.size());
  const Camera camera = test::look_camera({0.0, 2.0, 5.0}, {0.0, 0.5, 0.0}, 96, 72, 70.0);
  for (const SkipOptions skip : {SkipOptions{}, SkipOptions::none()}) {
    EmbreeTracer tracer(scene, options_with(skip));
    VisibilityBuffer full;
    TraceStats full_stats;
    tracer.trace(camera, full, full_stats);
    ASSERT_EQ(full.light_count, total);
    EXPECT_EQ(full_stats.lights_unrequested, 0u);
    const uint64_t hit = full_stats.pixels - full_stats.background_pixels;
    ASSERT_GT(hit, 0u);
    for (uint32_t n = 0; n <= total + 1; ++n) {  // total + 1: clamped to the scene's lights
      VisibilityBuffer subset;
      TraceStats stats;
      tracer.trace_lights(camera, n, subset, stats);
      const uint32_t traced = std::min(n, total);
      expect_subset_bits(full, subset, traced);
      EXPECT_EQ(stats.lights_unrequested, total - traced);
      EXPECT_EQ(stats.pixels, full_stats.pixels);
      EXPECT_EQ(stats.primary_rays, full_stats.primary_rays);
      // Every requested pixel-light pair is traced or skipped for a reason; unrequested pairs are neither.
      EXPECT_EQ(stats.shadow_rays + stats.skipped_backfacing + stats.skipped_out_of_range + stats.skipped_culled_light,
                hit * traced)
          << traced << " lights";
      if (!skip.backfacing) {
        EXPECT_EQ(stats.shadow_rays, hit * traced);
      }
      EXPECT_LE(stats.shadow_rays, full_stats.shadow_rays);
    }
  }
}

// A wrapper that implements only trace(): the interface's default keeps the first lights.
class TraceOnlyTracer final : public VisibilityTracer {
 public:
  explicit TraceOnlyTracer(VisibilityTracer& inner) : inner_(inner) {}
  TracerBackend backend() const override { return inner_.backend(); }
  std::string device_description() const override { return inner_.device_description(); }
  const AccelStats& accel_stats() const override { return inner_.accel_stats(); }
  uint32_t light_count() const override { return inner_.light_count(); }
  void trace(const Camera& camera, VisibilityBuffer& out, TraceStats& out_stats) override {
    inner_.trace(camera, out, out_stats);
  }

 private:
  VisibilityTracer& inner_;
};

TEST(LightSubset, DefaultForTraceOnlyWrappersKeepsTheFirstLights) {
  const Scene scene = nine_light_scene();
  const Camera camera = test::look_camera({0.0, 2.0, 5.0}, {0.0, 0.5, 0.0}, 64, 48, 70.0);
  EmbreeTracer tracer(scene, options_with(SkipOptions{}));
  TraceOnlyTracer wrapper(tracer);
  VisibilityBuffer full, direct, wrapped;
  TraceStats stats;
  tracer.trace(camera, full, stats);
  for (uint32_t n : {0u, 3u, 8u, 9u}) {
    tracer.trace_lights(camera, n, direct, stats);
    wrapper.trace_lights(camera, n, wrapped, stats);
    expect_subset_bits(full, wrapped, n);
    EXPECT_TRUE(direct == wrapped) << n;
  }
}

}  // namespace
}  // namespace dhr::server
