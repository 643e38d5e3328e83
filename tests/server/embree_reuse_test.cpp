// Reuse of traced visibility (trace/reuse/reuse_frame.hpp, EmbreeTracer::trace_reusing) against the exhaustive
// trace of the same camera (trace_layout, no reuse), which is the reference: a still camera gives identical bits with
// most pixels taken whole; a moving camera over a room with an occluder differs in at most kMaxDifferingShare of
// the hit pixel-light bits; a sphere light's levels are taken where neighbours agree (identical
// for a still camera), and its samples accumulate over frames (nearer a converged truth, fewer rays); a box that
// moves over a still camera's floor, and a light that moves, are traced again, never kept (identical bits); pixels
// near an eye-close wall that crosses the near plane are not taken; the same inputs give the same bits on 1 and 2
// threads. Plus the rule's pieces: the float projection against reproject(), the segment-box test, the refresh
// dither, the point-triangle query, the soft tally's sum and blend, the level hysteresis. Rule 1's borders and
// occluders: embree_reuse_rule1_test.cpp.
#include "trace/embree/embree_tracer.hpp"
#include "trace/soft/soft_image.hpp"
#include "trace/reuse/reuse_frame.hpp"
#include "test_animated_scene.hpp"
#include "reuse_pair.hpp"
#include "reuse_room.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

namespace dhr::server {
namespace {

using namespace reuse_test;  // the room, its cameras, the bound

TEST(ReuseRule, FloatProjectionAgreesWithReproject) {
  const Camera camera = camera_at(0.3, 1.6, 3.0);
  const glm::vec3 eye(camera.T_world_eye.position);
  const ReuseProjection p = ReuseProjection::of(camera, eye);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 x(u(rng), u(rng) * 0.5f + 1.0f, u(rng) - 2.0f);
    const Reprojection r = reproject(camera, glm::dvec3(x));
    glm::vec2 pixel;
    float depth = 0.0f;
    const bool in_front = p.project(x, pixel, depth);
    ASSERT_EQ(in_front, r.status != Reprojection::Status::kBehind);
    if (!in_front) continue;
    EXPECT_NEAR(pixel.x, r.pixel.x, 1e-2);
    EXPECT_NEAR(pixel.y, r.pixel.y, 1e-2);
    EXPECT_NEAR(depth, r.depth, 1e-4);
  }
}

TEST(ReuseRule, SegmentBoxTest) {
  const std::vector<ReuseBox> boxes{{glm::vec3(0.0f), glm::vec3(1.0f)}};
  EXPECT_FALSE(segment_misses_boxes(glm::vec3(-1, 0.5f, 0.5f), glm::vec3(2, 0.5f, 0.5f), boxes, 0.0f));
  EXPECT_TRUE(segment_misses_boxes(glm::vec3(-1, 1.5f, 0.5f), glm::vec3(2, 1.5f, 0.5f), boxes, 0.0f));
  EXPECT_FALSE(segment_misses_boxes(glm::vec3(-1, 1.5f, 0.5f), glm::vec3(2, 1.5f, 0.5f), boxes, 0.6f));  // widened
  EXPECT_TRUE(segment_misses_boxes(glm::vec3(-1, 0.5f, 0.5f), glm::vec3(-0.1f, 0.5f, 0.5f), boxes, 0.0f));  // short
  EXPECT_FALSE(segment_misses_boxes(glm::vec3(0.5f, 0.5f, 0.5f), glm::vec3(0.6f, 0.5f, 0.5f), boxes, 0.0f));
  const float nan = std::nanf("");
  EXPECT_FALSE(segment_misses_boxes(glm::vec3(nan, 0, 0), glm::vec3(2, 0.5f, 0.5f), boxes, 0.0f));  // NaN: traced
}

TEST(ReuseRule, RefreshVisitsEveryPixelOfABlockOnceIn16Frames) {
  for (uint32_t y = 0; y < 8; ++y)
    for (uint32_t x = 0; x < 8; ++x) {
      int hits = 0;
      for (uint32_t g = 100; g < 100 + kRefreshPeriod; ++g) hits += reuse_refresh_pixel(x, y, g) ? 1 : 0;
      EXPECT_EQ(hits, 1) << x << "," << y;
    }
  int per_frame = 0;
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 4; ++x) per_frame += reuse_refresh_pixel(x, y, 7) ? 1 : 0;
  EXPECT_EQ(per_frame, 1);
}

TEST(ReuseRule, PointQueryFindsTrianglesWithinRadiusAndRegion) {
  EmbreeTracer tracer(room(false, false), threads(1));
  const EmbreeScene& scene = tracer.embree_scene();
  const glm::vec3 above_floor = scene.to_relative(glm::dvec3(0.0, 0.05, 2.0));
  EXPECT_TRUE(scene.geometry_within(above_floor, 0.06f));
  EXPECT_FALSE(scene.geometry_within(above_floor, 0.04f));
  // Only the half-space y >= 0.1 (relative frame): the floor is not in it.
  const float floor_y = scene.to_relative(glm::dvec3(0.0, 0.1, 0.0)).y;
  EXPECT_FALSE(scene.geometry_within(above_floor, 0.06f, {glm::vec4(0, 1, 0, -floor_y)}));
  EXPECT_TRUE(scene.geometry_within(above_floor, 0.06f, {glm::vec4(0, -1, 0, floor_y)}));
}

TEST(EmbreeReuse, StillCameraGivesIdenticalBitsMostlyWithoutRays) {
  EmbreeTracer tracer(room(false, false), threads(2));
  const Camera camera = camera_at(0.3, 1.6, 3.0);
  std::array<ReuseFrame, 2> frames;
  ReusePair first = trace_both(tracer, camera, nullptr, frames[0]);
  EXPECT_EQ(first.reused, first.exact);
  EXPECT_EQ(first.reused_stats.reused_pixels, 0u);  // nothing to take from yet
  ASSERT_TRUE(frames[0].valid());
  for (int i = 1; i < 4; ++i) {
    ReusePair p = trace_both(tracer, camera, &frames[(i + 1) % 2], frames[i % 2]);
    EXPECT_EQ(p.reused, p.exact) << "frame " << i;
    const uint64_t hits = p.exact_stats.pixels - p.exact_stats.background_pixels;
    EXPECT_GT(p.reused_stats.reused_pixels, hits / 2) << "frame " << i;
    // Every pixel is either taken whole or traced.
    EXPECT_EQ(p.reused_stats.primary_rays + p.reused_stats.reused_pixels, p.exact_stats.primary_rays);
  }
}

TEST(EmbreeReuse, MovingCameraStaysWithinTheBoundAndReuses) {
  EmbreeTracer tracer(room(false, false), threads(2));
  std::array<ReuseFrame, 2> frames;
  uint64_t bits = 0, differing = 0, reused = 0, pixels = 0, rays = 0, exhaustive_rays = 0;
  for (int i = 0; i < 24; ++i) {
    // A head drifting sideways and forward at about 0.5 m/s (90 Hz), turning a little.
    const Camera camera = camera_at(0.3 + 0.006 * i, 1.6 - 0.001 * i, 3.0 - 0.004 * i);
    ReusePair p = trace_both(tracer, camera, i ? &frames[(i + 1) % 2] : nullptr, frames[i % 2]);
    const uint64_t hits = p.exact_stats.pixels - p.exact_stats.background_pixels;
    bits += hits * tracer.light_count();
    differing += differing_bits(p.exact, p.reused);
    reused += p.reused_stats.reused_pixels;
    pixels += p.exact_stats.pixels;
    rays += p.reused_stats.primary_rays + p.reused_stats.shadow_rays;
    exhaustive_rays += p.exact_stats.primary_rays + p.exact_stats.shadow_rays;
  }
  EXPECT_LE(static_cast<double>(differing), kMaxDifferingShare * static_cast<double>(bits));
  EXPECT_GT(reused, pixels / 3);
  EXPECT_LT(rays, exhaustive_rays / 2);
}

// A still camera, the box sliding over the floor: its shadow moves and no frame keeps the old one.
TEST(EmbreeReuse, MovingOccluderAndLightAreTracedAgain) {
  for (const bool light : {false, true}) {
    EmbreeTracer tracer(room(true, light), threads(2));
    const Camera camera = camera_at(0.0, 2.0, 3.5);
    std::array<ReuseFrame, 2> frames;
    uint64_t reused = 0;
    for (int i = 0; i < 12; ++i) {
      tracer.set_scene_time(0.05 * i);
      ReusePair p = trace_both(tracer, camera, i ? &frames[(i + 1) % 2] : nullptr, frames[i % 2]);
      EXPECT_EQ(p.reused, p.exact) << "frame " << i << (light ? " with the moving light" : "");
      reused += p.reused_stats.reused_pixels;
    }
    // Away from the box's shadow segments blocks are still taken, the moving light's pairs traced from their points.
    EXPECT_GT(reused, 0u);
  }
}

// The eye 3 cm from a wall, moving toward it: the wall crosses the near plane, so no block is taken whole.
TEST(EmbreeReuse, GeometryAtTheNearPlaneTurnsBlocksOff) {
  EmbreeTracer tracer(room(false, false), threads(2));
  std::array<ReuseFrame, 2> frames;
  for (int i = 0; i < 3; ++i) {
    const Camera camera = test::look_camera(glm::dvec3(1.0, 1.5, -3.97 + 0.01 * (1 - i)),
                                            glm::dvec3(1.0, 1.5, -5.0), 96, 64, 100.0);
    ReusePair p = trace_both(tracer, camera, i ? &frames[(i + 1) % 2] : nullptr, frames[i % 2]);
    EXPECT_EQ(p.reused, p.exact) << "frame " << i;
    if (i > 0) {
      EXPECT_EQ(p.reused_stats.reused_pixels, 0u) << "frame " << i;
    }
  }
}

// A sphere light (soft levels): a still camera's levels are taken where the neighbours hold one level, and they
// are the exhaustive trace's.
TEST(EmbreeReuse, SoftLevelsAreTakenWhereNeighboursAgree) {
  Scene scene = room(false, false);
  scene.lights[0].radius = 0.3f;
  EmbreeTracer tracer(scene, threads(2));
  const VisibilityLayout layout = layout_for_lights(tracer.light_extents(), tracer.light_count());
  ASSERT_TRUE(layout.is_soft(0));
  const Camera camera = camera_at(0.3, 1.6, 3.0, 192, 128);
  std::array<ReuseFrame, 2> frames;
  uint64_t reused_pairs = 0;
  for (int i = 0; i < 3; ++i) {
    VisibilityBuffer exact, reused;
    TraceStats xs, rs;
    tracer.trace_layout(camera, layout, exact, xs);
    ReuseRequest request;
    request.previous = i ? &frames[(i + 1) % 2] : nullptr;
    request.record = &frames[i % 2];
    request.options.soft_history = 0;  // rule 2 alone: accumulated samples change levels (the test below)
    tracer.trace_reusing(camera, layout, request, reused, rs);
    EXPECT_EQ(reused, exact) << "frame " << i;
    EXPECT_LT(rs.soft_shadow_rays, i ? xs.soft_shadow_rays : xs.soft_shadow_rays + 1);
    reused_pairs += rs.reused_pairs;
  }
  EXPECT_GT(reused_pairs, 0u);
}

// Mean |k - k truth| of soft light 0 over the truth's surface pixels.
double soft_error(const VisibilityBuffer& buffer, const VisibilityLayout& layout, const SoftImage& truth) {
  double sum = 0.0;
  size_t n = 0;
  for (uint32_t y = 0; y < truth.height; ++y)
    for (uint32_t x = 0; x < truth.width; ++x) {
      if (!truth.surface[size_t{y} * truth.width + x]) continue;
      sum += std::fabs(static_cast<double>(layout.visibility(buffer.get(x, y), 0)) -
                       static_cast<double>(truth.fraction[truth.index(x, y, 0)]));
      ++n;
    }
  return n ? sum / static_cast<double>(n) : 0.0;
}

// Soft samples accumulate (ReuseOptions::soft_history): a still camera's penumbra gathers more samples than one
// trace takes, with fewer rays per frame, and ends nearer a converged truth than the one-frame trace; off, the
// levels are the exhaustive trace's. The same inputs give the same levels on 1 and 2 threads.
TEST(EmbreeReuse, SoftSamplesAccumulateOnAStillCamera) {
  Scene scene = room(false, false);
  scene.lights[0].radius = 1.0f;
  // Looking down at the box's shadow: rule 2's surface checks (and so the history) hold on the floor there.
  const Camera camera = test::look_camera(glm::dvec3(0.3, 4.0, 1.5), glm::dvec3(0.0, 0.0, -1.0), 192, 128, 80.0);
  SoftImageOptions truth_options;
  truth_options.sampling = SoftOptions::uniform(1024, 7, SoftPattern::kPerPixel);
  SoftImage truth;
  std::array<VisibilityBuffer, 2> last;
  std::array<uint64_t, 2> last_rays{};
  VisibilityBuffer exact;
  uint64_t exact_rays = 0;
  for (uint32_t n : {1u, 2u}) {
    // Few samples with a scramble per pixel: one trace's levels are noisy, so what accumulates shows.
    TracerOptions options = threads(n);
    options.soft = SoftOptions{4, 8, 0, SoftPattern::kPerPixel};
    EmbreeTracer tracer(scene, options);
    const VisibilityLayout layout = layout_for_lights(tracer.light_extents(), tracer.light_count());
    if (n == 1) {
      trace_soft_image(tracer.embree_scene(), scene.lights, camera, truth_options, truth);
      TraceStats xs;
      tracer.trace_layout(camera, layout, exact, xs);
      exact_rays = xs.soft_shadow_rays;
    }
    std::array<ReuseFrame, 2> frames;
    for (int i = 0; i < 8; ++i) {
      TraceStats rs;
      ReuseRequest request;
      request.previous = i ? &frames[(i + 1) % 2] : nullptr;
      request.record = &frames[i % 2];
      tracer.trace_reusing(camera, layout, request, last[n - 1], rs);
      if (i == 0) {
        EXPECT_EQ(last[n - 1], exact);  // nothing accumulated yet: the exhaustive levels
      }
      last_rays[n - 1] = rs.soft_shadow_rays;
    }
    const std::vector<SoftTally>& tally = frames[7 % 2].tally;
    ASSERT_EQ(frames[7 % 2].tally_stride, 1u);  // one soft light: one tally per pixel
    ASSERT_EQ(tally.size(), frames[0].mesh.size());
    uint32_t most = 0;
    for (const SoftTally& t : tally) most = std::max<uint32_t>(most, t.samples);
    EXPECT_GT(most, options.soft.max_samples);  // more samples than one trace takes
    if (n == 1) {
      const double accumulated = soft_error(last[0], layout, truth), one_frame = soft_error(exact, layout, truth);
      EXPECT_LT(accumulated, one_frame);
      EXPECT_LT(last_rays[0], exact_rays);
    }
  }
  EXPECT_EQ(last[0], last[1]);
}

// The level hysteresis (ReuseOptions::soft_hysteresis): with the same accumulating traces of a still camera, a
// pixel's level flips between traces less often with it than with the nearest level, and the levels stay nearer the
// converged truth than one trace's.
TEST(EmbreeReuse, SoftLevelsFlipLessWithHysteresis) {
  Scene scene = room(false, false);
  scene.lights[0].radius = 1.0f;
  const Camera camera = test::look_camera(glm::dvec3(0.3, 4.0, 1.5), glm::dvec3(0.0, 0.0, -1.0), 192, 128, 80.0);
  TracerOptions options = threads(1);
  options.soft = SoftOptions{4, 8, 0, SoftPattern::kPerPixel};
  EmbreeTracer tracer(scene, options);
  const VisibilityLayout layout = layout_for_lights(tracer.light_extents(), tracer.light_count());
  SoftImageOptions truth_options;
  truth_options.sampling = SoftOptions::uniform(1024, 7, SoftPattern::kPerPixel);
  SoftImage truth;
  trace_soft_image(tracer.embree_scene(), scene.lights, camera, truth_options, truth);
  VisibilityBuffer exact;
  TraceStats xs;
  tracer.trace_layout(camera, layout, exact, xs);
  auto run = [&](float hysteresis, VisibilityBuffer& last) {
    std::array<ReuseFrame, 2> frames;
    VisibilityBuffer previous;
    uint64_t flips = 0;
    for (int i = 0; i < 8; ++i) {
      TraceStats rs;
      ReuseRequest request;
      request.previous = i ? &frames[(i + 1) % 2] : nullptr;
      request.record = &frames[i % 2];
      request.options.soft_hysteresis = hysteresis;
      tracer.trace_reusing(camera, layout, request, last, rs);
      if (i > 0)
        for (uint32_t y = 0; y < last.height; ++y)
          for (uint32_t x = 0; x < last.width; ++x)
            flips += layout.field(last.get(x, y), 0) != layout.field(previous.get(x, y), 0) ? 1 : 0;
      previous = last;
    }
    return flips;
  };
  VisibilityBuffer nearest, held;
  const uint64_t flips_nearest = run(0.0f, nearest), flips_held = run(0.25f, held);
  EXPECT_GT(flips_nearest, 0u);  // the accumulating samples move levels
  EXPECT_LT(flips_held, flips_nearest);
  EXPECT_LT(soft_error(held, layout, truth), soft_error(exact, layout, truth));
}

TEST(ReuseRule, SoftLevelHysteresisHoldsTheHistorysLevel) {
  const float level = 1.0f / 7.0f;
  EXPECT_EQ(soft_level_hysteresis(3.7f * level, 3.0f * level, 0.0f), 3.7f * level);  // off: the share itself
  EXPECT_FLOAT_EQ(soft_level_hysteresis(3.7f * level, 3.0f * level, 0.25f), 3.0f * level);  // within 0.75: held
  EXPECT_FLOAT_EQ(soft_level_hysteresis(2.3f * level, 3.0f * level, 0.25f), 3.0f * level);
  EXPECT_EQ(soft_level_hysteresis(3.8f * level, 3.0f * level, 0.25f), 3.8f * level);  // beyond: its own level
  EXPECT_EQ(soft_level_hysteresis(2.2f * level, 3.0f * level, 0.25f), 2.2f * level);
  EXPECT_FLOAT_EQ(soft_level_hysteresis(3.6f * level, 2.8f * level, 0.25f), 3.0f * level);  // the history's nearest
  EXPECT_FLOAT_EQ(soft_level_hysteresis(0.5f * level, 0.0f, 0.25f), 0.0f);
}

TEST(ReuseRule, SoftTallyAddsSamplesUpToTheCap) {
  SoftTally t = add_soft_samples(SoftHistory{}, 3, 8, 128);
  EXPECT_EQ(t.samples, 8);
  EXPECT_NEAR(tally_fraction(t), 3.0 / 8.0, 1e-4);
  t = add_soft_samples(SoftHistory{0.5f, 120.0f}, 8, 8, 128);  // 60 + 8 of 128
  EXPECT_EQ(t.samples, 128);
  EXPECT_NEAR(tally_fraction(t), 68.0 / 128.0, 1e-4);
  t = add_soft_samples(SoftHistory{0.5f, 500.0f}, 0, 8, 128);  // the history weighs 120
  EXPECT_EQ(t.samples, 128);
  EXPECT_NEAR(tally_fraction(t), 60.0 / 128.0, 1e-4);
  t = add_soft_samples(SoftHistory{0.25f, 64.0f}, 0, 0, 128);  // kept as it was
  EXPECT_EQ(t.samples, 64);
  EXPECT_NEAR(tally_fraction(t), 0.25, 1e-4);
  EXPECT_EQ(add_soft_samples(SoftHistory{}, 0, 0, 128).samples, 0);
}

TEST(ReuseRule, SoftHistoryBlendsTheCornersWithinOneLevel) {
  ReuseFrame frame;
  frame.tally_stride = 1;
  frame.tally.assign(4, SoftTally{});
  ReuseCorners corners;
  for (int k = 0; k < 4; ++k) {
    corners.index[k] = static_cast<size_t>(k);
    corners.weight[k] = 0.25f;
  }
  auto share = [](double f) { return static_cast<uint16_t>(std::lround(f * 65535.0)); };
  frame.tally[0] = {share(0.5), 32};
  frame.tally[1] = {share(0.6), 32};
  frame.tally[2] = {share(0.5), 64};
  EXPECT_EQ(reuse_soft_history(frame, corners, 0).samples, 0.0f);  // a corner without a tally
  frame.tally[3] = {share(0.6), 64};
  SoftHistory h = reuse_soft_history(frame, corners, 0);
  EXPECT_NEAR(h.samples, 48.0, 1e-3);
  EXPECT_NEAR(h.fraction, (0.5 * 32 + 0.6 * 32 + 0.5 * 64 + 0.6 * 64) / 192.0, 1e-4);
  frame.tally[3] = {share(0.7), 64};  // more than one level (1/7) apart: a steep penumbra, no history
  EXPECT_EQ(reuse_soft_history(frame, corners, 0).samples, 0.0f);
  EXPECT_EQ(reuse_soft_history(frame, corners, 1).samples, 0.0f);  // not a slot of the frame
}

TEST(EmbreeReuse, SameBitsOnOneAndTwoThreads) {
  const Scene scene = room(false, false);
  std::array<VisibilityBuffer, 2> last;
  for (uint32_t n : {1u, 2u}) {
    EmbreeTracer tracer(scene, threads(n));
    std::array<ReuseFrame, 2> frames;
    for (int i = 0; i < 5; ++i) {
      ReusePair p = trace_both(tracer, camera_at(0.3 + 0.01 * i, 1.6, 3.0), i ? &frames[(i + 1) % 2] : nullptr,
                          frames[i % 2]);
      last[n - 1] = p.reused;
    }
  }
  EXPECT_EQ(last[0], last[1]);
}

TEST(EmbreeReuse, RecordIsLeftInvalidByTheDefaultImplementation) {
  // A tracer that only implements trace_layout (the Vulkan backend) traces everything and keeps no record.
  struct Wrapped : VisibilityTracer {
    EmbreeTracer inner{room(false, false), threads(1)};
    TracerBackend backend() const override { return inner.backend(); }
    std::string device_description() const override { return "wrapped"; }
    const AccelStats& accel_stats() const override { return inner.accel_stats(); }
    uint32_t light_count() const override { return inner.light_count(); }
    void trace(const Camera& c, VisibilityBuffer& out, TraceStats& s) override { inner.trace(c, out, s); }
    void trace_layout(const Camera& c, const VisibilityLayout& l, VisibilityBuffer& out, TraceStats& s) override {
      inner.trace_layout(c, l, out, s);
    }
  } wrapped;
  ReuseFrame record;
  record.mesh.assign(4, 0);
  record.edge_distance.assign(1, 0);
  ReusePair p = trace_both(wrapped, camera_at(0.3, 1.6, 3.0), nullptr, record);
  EXPECT_EQ(p.reused, p.exact);
  EXPECT_FALSE(record.valid());
}

}  // namespace
}  // namespace dhr::server
