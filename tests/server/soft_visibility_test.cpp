// Fractional (soft) visibility on the Embree backend (server/trace/soft): analytic visible fractions of a sphere
// light behind a plane's edge and behind a disk, a rect light fully visible / hidden / seen from behind,
// determinism, the adaptive estimate against a many-sample one, punctual lights against the hard tracer's bits on
// the default room, and the sample sequence, the sampler's geometry, quantization and Gray code.
#include "trace/embree/embree_trace_tile.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "trace/soft/light_sampler.hpp"
#include "trace/soft/soft_image.hpp"
#include "visibility/soft_levels.hpp"
#include "trace/soft/soft_visibility.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <glm/geometric.hpp>

#include <bitset>
#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>

namespace dhr::server {
namespace {

using test::add_grid;
using test::finalize;

// A horizontal regular polygon (n sides, CCW from above) centred at c: a disk occluder with a known area.
void add_disk(Scene& scene, const glm::vec3& c, float radius, uint32_t n, uint32_t material) {
  SceneMesh mesh;
  mesh.name = "disk";
  mesh.material = material;
  mesh.geometry = static_cast<uint32_t>(scene.meshes.size());
  mesh.positions.push_back(c);
  for (uint32_t i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * i / n;
    mesh.positions.push_back(c + radius * glm::vec3(std::cos(a), 0.0, -std::sin(a)));
  }
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0, 1, 0));
  for (uint32_t i = 0; i < n; ++i) mesh.indices.insert(mesh.indices.end(), {0, 1 + i, 1 + (i + 1) % n});
  scene.meshes.push_back(std::move(mesh));
}

// The floor y = 0 (20 x 20 m, facing up) plus whatever `more` adds.
template <typename F>
Scene floor_scene(F&& more) {
  Scene scene = test::make_empty_scene();
  add_grid(scene, {-10, 0, 10}, {20, 0, 0}, {0, 0, -20}, 4, test::kSingleSided);
  more(scene);
  finalize(scene);
  return scene;
}

SceneLight sphere_light(const glm::vec3& c, float radius) {
  SceneLight l = test::point_light(c, 10.0f);
  l.radius = radius;
  return l;
}

// Rect light facing down (emitting along -Y): tangent +X, bitangent -Z (so that -Z of its node is -Y).
SceneLight rect_light(const glm::vec3& c, float width, float height) {
  SceneLight l;
  l.type = SceneLight::Type::kRect;
  l.name = "rect";
  l.position = c;
  l.direction = glm::vec3(0, -1, 0);
  l.tangent = glm::vec3(1, 0, 0);
  l.bitangent = glm::vec3(0, 0, -1);
  l.width = width;
  l.height = height;
  l.intensity = 10.0f;
  return l;
}

// A disk emitter facing down (as rect_light): diameter `width` along +X, `height` along -Z.
SceneLight disk_light(const glm::vec3& c, float width, float height) {
  SceneLight l = rect_light(c, width, height);
  l.type = SceneLight::Type::kDisk;
  return l;
}

// A disk sun shining along `direction`, 0.1 rad across.
SceneLight sun_light(const glm::vec3& direction) {
  SceneLight l = test::directional_light(direction);
  l.angle = 0.1f;
  return l;
}

// The floor and a double-sided plane x < 0 at y = 2 (its edge along z at x = 0), lit by `lights`.
Scene edge_scene(std::vector<SceneLight> lights) {
  return floor_scene([&](Scene& s) {
    add_grid(s, {-10, 2, 10}, {10, 0, 0}, {0, 0, -20}, 2, test::kDoubleSided);
    s.lights = std::move(lights);
  });
}

// A floor point facing up, in the Embree scene's relative frame.
SurfaceHit floor_hit(const EmbreeScene& es, const glm::dvec3& world) {
  SurfaceHit h;
  h.position = es.to_relative(world);
  h.geometric_normal = h.shading_normal = glm::vec3(0, 1, 0);
  return h;
}

// Mean fraction over `seeds` independent scrambles (pixels) of one point.
double mean_fraction(const EmbreeScene& es, const SampledLight& light, const SurfaceHit& hit, const SoftOptions& o,
                     uint32_t seeds) {
  double sum = 0.0;
  for (uint32_t s = 0; s < seeds; ++s) sum += static_cast<double>(soft_visibility(es, light, hit, soft_seed(s, 7, 0), o).fraction);
  return sum / seeds;
}

const glm::vec3 kLightCentre(0, 4, 0);
constexpr float kLightRadius = 0.5f;

// The occluder's edge (x = 0 at y = 2) and the light's centre lie in one plane through the floor point at the
// origin: the plane x < 0 hides exactly half the cap (by symmetry), so the visible fraction is 0.5.
TEST(SoftVisibility, SphereHalfHiddenBehindPlaneEdge) {
  const Scene scene = edge_scene({sphere_light(kLightCentre, kLightRadius)});
  const auto es = EmbreeScene::create(scene);
  const SampledLight light = make_sampled_light(scene.lights[0], es->origin());
  const SurfaceHit hit = floor_hit(*es, {0, 0, 0});
  // 1024 stratified samples: bound 0.01. Default adaptive (32 samples): each within 0.1, the mean of 64
  // independent scrambles within 0.02 (unbiased).
  EXPECT_NEAR(soft_visibility(*es, light, hit, soft_seed(1, 2, 0), SoftOptions::uniform(1024)).fraction, 0.5, 0.01);
  for (uint32_t s = 0; s < 16; ++s) {
    const SoftSample r = soft_visibility(*es, light, hit, soft_seed(s, 3, 0), SoftOptions{});
    EXPECT_NEAR(r.fraction, 0.5, 0.1) << s;
    EXPECT_TRUE(r.refined);
    EXPECT_EQ(r.samples, 32u);
  }
  EXPECT_NEAR(mean_fraction(*es, light, hit, SoftOptions{}, 64), 0.5, 0.02);
}

// The same plane edge halves every shape whose centre lies in the plane through the point and the edge: a disk sun
// straight overhead, and rect and disk emitters (uniform over their area, symmetric about that plane).
TEST(SoftVisibility, EveryShapeHalfHiddenBehindPlaneEdge) {
  const Scene scene = edge_scene({sun_light({0.0f, -1.0f, 0.0f}), rect_light({0, 4, 0}, 1.0f, 0.5f),
                                  disk_light({0, 4, 0}, 1.0f, 1.0f)});
  const auto es = EmbreeScene::create(scene);
  const SurfaceHit hit = floor_hit(*es, {0, 0, 0});
  for (const SceneLight& l : scene.lights) {
    const SampledLight light = make_sampled_light(l, es->origin());
    ASSERT_NE(light.shape, SampledLight::Shape::kPunctual) << l.name;
    EXPECT_NEAR(soft_visibility(*es, light, hit, soft_seed(1, 2, 0), SoftOptions::uniform(1024)).fraction, 0.5, 0.01)
        << l.name;
    EXPECT_NEAR(mean_fraction(*es, light, hit, SoftOptions{}, 64), 0.5, 0.02) << l.name;
  }
}

// With one scramble per light a batch prepares each (seed, shape)'s sample points once and keeps a few: the results
// must be bit for bit those of preparing every sample of every pair (the per-pixel pattern's path), also when the
// pairs interleave more seeds than the batch keeps (entries replaced, then made again and extended).
TEST(SoftVisibility, SharedSamplePointsGiveTheSameResults) {
  const Scene scene = edge_scene({sphere_light(kLightCentre, kLightRadius), sun_light({0.3f, -1.0f, 0.2f}),
                                  rect_light({-0.3f, 4, 0}, 1.0f, 0.5f), disk_light({0.4f, 4, 0.3f}, 1.0f, 0.7f)});
  const auto es = EmbreeScene::create(scene);
  std::vector<SampledLight> lights;
  for (const SceneLight& l : scene.lights) lights.push_back(make_sampled_light(l, es->origin()));
  std::vector<SurfaceHit> hits;
  for (int i = 0; i < 24; ++i) hits.push_back(floor_hit(*es, {-1.2 + 0.1 * i, 0.0, 0.05 * (i % 5)}));
  SoftOptions shared;  // adaptive 8 / 32: refined pairs extend their entry
  ASSERT_EQ(shared.pattern, SoftPattern::kPerLight);
  SoftOptions each = shared;
  each.pattern = SoftPattern::kPerPixel;  // the same seeds, every sample prepared on its own
  std::vector<SoftPair> pairs;
  for (size_t h = 0; h < hits.size(); ++h)
    for (uint32_t li = 0; li < lights.size(); ++li)  // 4 shapes x 2 seeds each: more than the batch keeps
      pairs.push_back({&lights[li], &hits[h], soft_seed(0, 0, li, static_cast<uint32_t>(h % 2)), 0, 0, 0, {}});
  SoftScratch scratch;
  soft_visibility_batch(*es, pairs, shared, scratch);
  size_t refined = 0, penumbra = 0;
  for (const SoftPair& p : pairs) {
    const SoftSample ref = soft_visibility(*es, *p.light, *p.hit, p.seed, each);
    EXPECT_EQ(p.result.fraction, ref.fraction);
    EXPECT_EQ(p.result.rays, ref.rays);
    EXPECT_EQ(p.result.samples, ref.samples);
    refined += p.result.refined;
    penumbra += p.result.fraction > 0.0f && p.result.fraction < 1.0f;
  }
  EXPECT_GT(refined, 10u);
  EXPECT_GT(penumbra, 10u);
}

// A disk occluder of radius a at height h centred on the axis hides the directions with tan(theta) < a / h; the
// cap is sin(theta_max) = r / d: visible = (cos theta_b - cos theta_max) / (1 - cos theta_max).
TEST(SoftVisibility, SphereBehindDiskMatchesCapFraction) {
  constexpr float kDiskRadius = 0.2f, kDiskHeight = 2.0f;
  constexpr uint32_t kSides = 256;  // inscribed polygon: its area is within 0.02 % of the disk's
  const Scene scene = floor_scene([&](Scene& s) {
    add_disk(s, {0, kDiskHeight, 0}, kDiskRadius, kSides, test::kDoubleSided);
    s.lights = {sphere_light(kLightCentre, kLightRadius)};
  });
  const double d = kLightCentre.y, r = kLightRadius;
  const double cos_max = std::sqrt(1.0 - (r / d) * (r / d));
  const double tan_b = static_cast<double>(kDiskRadius) / static_cast<double>(kDiskHeight);
  const double cos_b = 1.0 / std::sqrt(1.0 + tan_b * tan_b);
  const double expected = (cos_b - cos_max) / (1.0 - cos_max);  // 0.367
  const auto es = EmbreeScene::create(scene);
  const SampledLight light = make_sampled_light(scene.lights[0], es->origin());
  const SurfaceHit hit = floor_hit(*es, {0, 0, 0});
  EXPECT_NEAR(soft_visibility(*es, light, hit, soft_seed(4, 5, 0), SoftOptions::uniform(1024)).fraction, expected,
              0.01);
  EXPECT_NEAR(mean_fraction(*es, light, hit, SoftOptions{}, 64), expected, 0.02);
  // Seen from beside the disk's shadow the light is fully visible: the first samples only, exactly 1.
  const SoftSample clear = soft_visibility(*es, light, floor_hit(*es, {3, 0, 0}), soft_seed(0, 0, 0), SoftOptions{});
  EXPECT_EQ(clear.fraction, 1.0f);
  EXPECT_EQ(clear.rays, SoftOptions{}.initial_samples);
  EXPECT_FALSE(clear.refined);
}

TEST(SoftVisibility, RectVisibleHiddenAndBehind) {
  const Scene scene = floor_scene([](Scene& s) {
    // Occluder 1 m above the floor over x in [4, 8]: hides the light from floor points below it.
    add_grid(s, {4, 1, 4}, {4, 0, 0}, {0, 0, -8}, 1, test::kDoubleSided);
    s.lights = {rect_light({0, 3, 0}, 1.0f, 0.5f), rect_light({6, 3, 0}, 1.0f, 0.5f)};
  });
  const auto es = EmbreeScene::create(scene);
  const SampledLight open = make_sampled_light(scene.lights[0], es->origin());
  const SampledLight covered = make_sampled_light(scene.lights[1], es->origin());
  ASSERT_EQ(open.shape, SampledLight::Shape::kRect);
  const SoftSample visible = soft_visibility(*es, open, floor_hit(*es, {0.3, 0, 0.2}), soft_seed(0, 0, 0), {});
  EXPECT_EQ(visible.fraction, 1.0f);
  EXPECT_EQ(visible.rays, SoftOptions{}.initial_samples);
  const SoftSample hidden = soft_visibility(*es, covered, floor_hit(*es, {6, 0, 0}), soft_seed(0, 0, 1), {});
  EXPECT_EQ(hidden.fraction, 0.0f);
  EXPECT_EQ(hidden.rays, SoftOptions{}.initial_samples);
  // Above the emitter, facing it: a one-sided emitter sends nothing up; the light test at its centre already says
  // so (light_eval: behind a rect or disk light is out of range). No ray.
  SurfaceHit above = floor_hit(*es, {0, 5, 0});
  above.geometric_normal = above.shading_normal = glm::vec3(0, -1, 0);
  const SoftSample behind = soft_visibility(*es, open, above, soft_seed(0, 0, 0), SoftOptions::uniform(64));
  EXPECT_EQ(behind.test, LightTest::kOutOfRange);
  EXPECT_EQ(behind.fraction, 0.0f);
  EXPECT_EQ(behind.rays, 0u);
  // Every sample ends on the rect: within its half extents, in its plane.
  const auto view = LightView::create(open, es->to_relative(glm::dvec3(0.3, 0.01, 0.2)));
  ASSERT_TRUE(view);
  for (uint32_t i = 0; i < 64; ++i) {
    const SampleRay s = view->sample(sample_2d(i, 99));
    const glm::dvec3 q = glm::dvec3(es->to_relative(glm::dvec3(0.3, 0.01, 0.2))) +
                         glm::dvec3(s.dir) * (static_cast<double>(s.tfar) / static_cast<double>(detail::kShadowTfarScale));
    const glm::dvec3 local = q - open.centre;
    EXPECT_NEAR(local.y, 0.0, 1e-5);
    EXPECT_LE(std::fabs(local.x), 0.5 + 1e-5);
    EXPECT_LE(std::fabs(local.z), 0.25 + 1e-5);
  }
}

// A floor with a floating box, a sphere light, a rect light and a sun with a disk: soft shadows on the floor.
Scene soft_room() {
  return floor_scene([](Scene& s) {
    test::add_box(s, {-0.5f, 0.5f, -0.5f}, {0.5f, 1.5f, 0.5f}, test::kSingleSided);
    SceneLight sun = test::directional_light({-0.3f, -1.0f, -0.2f});
    sun.angle = 0.05f;
    s.lights = {sphere_light({1.0f, 3.5f, 0.5f}, 0.4f), rect_light({-1.5f, 3.0f, 0.0f}, 1.2f, 0.6f), sun};
  });
}

Camera soft_camera() { return test::look_camera({0.0, 5.0, 6.0}, {0.0, 0.0, 0.0}, 96, 72); }

TEST(SoftVisibility, ImageIsDeterministicForAnyThreadCount) {
  const Scene scene = soft_room();
  const auto es = EmbreeScene::create(scene);
  SoftImageOptions one, two;
  one.threads = 1;
  two.threads = 2;
  SoftImage a, b;
  const SoftStats sa = trace_soft_image(*es, scene.lights, soft_camera(), one, a);
  const SoftStats sb = trace_soft_image(*es, scene.lights, soft_camera(), two, b);
  EXPECT_EQ(a.level, b.level);
  EXPECT_EQ(a.fraction, b.fraction);
  EXPECT_EQ(sa.shadow_rays, sb.shadow_rays);
  EXPECT_EQ(sa.refined_pairs, sb.refined_pairs);
  // The scene has penumbrae (some pairs refined) and is mostly uniform (most stop after 4 rays).
  EXPECT_GT(sa.refined_pairs, 0u);
  EXPECT_LT(sa.refined_share(), 0.1);  // measured 0.009 (4.26 rays per pair)
  EXPECT_EQ(sa.pairs, (sa.pixels - sa.background_pixels) * scene.lights.size());
  // surface marks exactly the pixels whose primary ray hit.
  ASSERT_EQ(a.surface.size(), sa.pixels);
  EXPECT_EQ(a.surface, b.surface);
  EXPECT_EQ(static_cast<uint64_t>(std::count(a.surface.begin(), a.surface.end(), uint8_t{1})),
            sa.pixels - sa.background_pixels);
  EXPECT_GT(sa.background_pixels, 0u) << "the camera sees some background";
  // Every pair is sampled or skipped for one counted reason.
  EXPECT_EQ(sa.pairs, sa.contributing_pairs + sa.skipped_backfacing + sa.skipped_out_of_range);
  for (size_t i = 0; i < a.fraction.size(); ++i) ASSERT_EQ(a.level[i], quantize(a.fraction[i], a.levels));
}

TEST(SoftVisibility, UnusableOptionsAreRejected) {
  const Scene scene = soft_room();
  const auto es = EmbreeScene::create(scene);
  SoftImage out;
  auto trace_with = [&](const SoftImageOptions& o) { trace_soft_image(*es, scene.lights, soft_camera(), o, out); };
  SoftImageOptions o;
  o.sampling = SoftOptions{0, 4, 0};
  EXPECT_THROW(trace_with(o), std::invalid_argument);
  o.sampling = SoftOptions{8, 4, 0};
  EXPECT_THROW(trace_with(o), std::invalid_argument);
  o.sampling = SoftOptions::uniform(kMaxSoftSamples + 1);
  EXPECT_THROW(trace_with(o), std::invalid_argument);
  o = SoftImageOptions{};
  o.levels = 1;
  EXPECT_THROW(trace_with(o), std::invalid_argument);
  o.levels = kMaxSoftLevels + 1;
  EXPECT_THROW(trace_with(o), std::invalid_argument);
  o = SoftImageOptions{};
  o.tile_size = 6;
  EXPECT_THROW(trace_with(o), std::invalid_argument);
}

// Mean |adaptive - 1024-sample uniform| over the pairs where the light contributes, and over the reference's
// penumbra (0 < ref < 1), where all the error is.
TEST(SoftVisibility, AdaptiveAgreesWithManySampleUniform) {
  const Scene scene = soft_room();
  const auto es = EmbreeScene::create(scene);
  SoftImageOptions adaptive, reference;
  reference.sampling = SoftOptions::uniform(1024, /*salt=*/1);
  SoftImage a, ref;
  const SoftStats sa = trace_soft_image(*es, scene.lights, soft_camera(), adaptive, a);
  trace_soft_image(*es, scene.lights, soft_camera(), reference, ref);
  double sum = 0.0, penumbra_sum = 0.0;
  size_t n = 0, penumbra = 0;
  for (size_t i = 0; i < a.fraction.size(); ++i) {
    if (ref.rays[i] == 0) continue;  // the light cannot contribute (or nothing was hit)
    const double e = std::fabs(static_cast<double>(a.fraction[i]) - static_cast<double>(ref.fraction[i]));
    sum += e;
    ++n;
    if (ref.fraction[i] > 0.0f && ref.fraction[i] < 1.0f) {
      penumbra_sum += e;
      ++penumbra;
    }
  }
  ASSERT_GT(n, 10000u);
  ASSERT_GT(penumbra, 100u);
  // Measured 0.0004 and 0.030 (216 penumbra pairs); the bounds leave room for other Embree versions' edge decisions.
  EXPECT_LT(sum / static_cast<double>(n), 0.002) << "rays/pair " << sa.rays_per_pair();
  EXPECT_LT(penumbra_sum / static_cast<double>(penumbra), 0.06) << "penumbra pairs " << penumbra << " of " << n;
}

// No light has an extent: every fraction is 0 or 1 and equals the hard tracer's bit, pixel by pixel.
TEST(SoftVisibility, PunctualLightsGiveTheHardTracersBits) {
  const Scene scene = test::load_scene_or_fail(test::source_path(kDefaultScenePath));
  ASSERT_FALSE(scene.lights.empty());
  for (const SceneLight& l : scene.lights) ASSERT_FALSE(l.has_extent());
  TracerOptions to;
  to.threads = 2;
  EmbreeTracer tracer(scene, to);
  const auto cameras = test::bookmark_cameras(test::source_path(kDefaultScenePath), Extent{128, 96});
  ASSERT_FALSE(cameras.empty());
  for (const Camera& camera : cameras) {
    VisibilityBuffer hard;
    TraceStats hs;
    tracer.trace(camera, hard, hs);
    SoftImage soft;
    SoftImageOptions so;
    so.threads = 2;
    const SoftStats ss = trace_soft_image(tracer.embree_scene(), scene.lights, camera, so, soft);
    EXPECT_EQ(ss.shadow_rays, hs.shadow_rays);
    EXPECT_EQ(ss.refined_pairs, 0u);
    size_t mismatches = 0;
    for (uint32_t y = 0; y < camera.extent.height; ++y) {
      for (uint32_t x = 0; x < camera.extent.width; ++x) {
        for (uint32_t l = 0; l < soft.lights; ++l) {
          const bool bit = (hard.get(x, y) >> l) & 1u;
          const size_t i = soft.index(x, y, l);
          if (soft.fraction[i] != (bit ? 1.0f : 0.0f) || soft.level[i] != (bit ? soft.levels - 1 : 0u)) ++mismatches;
        }
      }
    }
    EXPECT_EQ(mismatches, 0u);
  }
}

// The shipped pattern (kPerLight) samples the same points of the light from every pixel, so a penumbra's levels
// change along contours: across a straight edge under a rect light the fraction only grows, point by point (a
// sample's ray clears the edge once and stays clear), adaptive stops included. kPerPixel scrambles per pixel.
TEST(SoftVisibility, PerLightPatternGivesMonotonePenumbraAcrossAnEdge) {
  const Scene scene = floor_scene([](Scene& s) {
    add_grid(s, {-10, 2, 10}, {10, 0, 0}, {0, 0, -20}, 2, test::kDoubleSided);  // hides x < 0 at y = 2
    s.lights = {rect_light({0, 4, 0}, 1.0f, 0.5f)};
  });
  const auto es = EmbreeScene::create(scene);
  const SampledLight light = make_sampled_light(scene.lights[0], es->origin());
  const SoftOptions shipped;
  ASSERT_EQ(shipped.pattern, SoftPattern::kPerLight);
  EXPECT_EQ(shipped.seed(3, 4, 0), shipped.seed(5, 6, 0));
  EXPECT_NE(shipped.seed(3, 4, 0), shipped.seed(3, 4, 1));
  SoftOptions per_pixel;
  per_pixel.pattern = SoftPattern::kPerPixel;
  EXPECT_NE(per_pixel.seed(3, 4, 0), per_pixel.seed(5, 6, 0));
  float previous = 0.0f;
  size_t partial = 0;
  for (int i = 0; i <= 300; ++i) {
    const double x = -1.5 + 0.01 * i;
    const float k = soft_visibility(*es, light, floor_hit(*es, {x, 0, 0}), shipped.seed(static_cast<uint32_t>(i), 0, 0),
                                    shipped).fraction;
    EXPECT_GE(k, previous) << "x " << x;
    if (k > 0.0f && k < 1.0f) ++partial;
    previous = k;
  }
  EXPECT_EQ(previous, 1.0f);
  EXPECT_GT(partial, 20u);  // the penumbra is about 1 m wide here: many points see part of the light
}

TEST(SoftVisibility, SequencePrefixesAreStratifiedAndSeedsDiffer) {
  for (uint32_t seed : {0u, 1u, 12345u, soft_seed(3, 4, 5)}) {
    // A (0,k,2)-net: the first 2^k points put one point in each cell of every 2^a x 2^(k-a) grid.
    for (uint32_t k = 1; k <= 8; ++k) {
      const uint32_t n = 1u << k;
      for (uint32_t a = 0; a <= k; ++a) {
        const uint32_t nx = 1u << a, ny = 1u << (k - a);
        std::set<uint32_t> cells;
        for (uint32_t i = 0; i < n; ++i) {
          const glm::vec2 u = sample_2d(i, seed);
          ASSERT_GE(u.x, 0.0f);
          ASSERT_LT(u.x, 1.0f);
          ASSERT_GE(u.y, 0.0f);
          ASSERT_LT(u.y, 1.0f);
          cells.insert(static_cast<uint32_t>(u.x * static_cast<float>(nx)) * ny +
                       static_cast<uint32_t>(u.y * static_cast<float>(ny)));
        }
        EXPECT_EQ(cells.size(), n) << "seed " << seed << " k " << k << " a " << a;
      }
    }
  }
  EXPECT_NE(sample_2d(0, soft_seed(0, 0, 0)), sample_2d(0, soft_seed(1, 0, 0)));
  EXPECT_NE(soft_seed(0, 0, 0), soft_seed(0, 0, 0, 1));
  EXPECT_EQ(sample_2d(5, 77), sample_2d(5, 77));
}

TEST(SoftVisibility, ConeSamplesStayInTheCap) {
  SceneLight sun = test::directional_light({0.0f, -1.0f, 0.0f});
  sun.angle = 0.0093f;  // the sun's angular diameter
  const SampledLight s = make_sampled_light(sun, glm::dvec3(0.0));
  ASSERT_EQ(s.shape, SampledLight::Shape::kSunDisk);
  const auto view = LightView::create(s, glm::vec3(0.0f));
  ASSERT_TRUE(view);
  const double cap = 2.0 * std::numbers::pi * (1.0 - std::cos(0.00465));
  EXPECT_NEAR(view->cone_solid_angle(), cap, cap * 1e-6);  // kept in float
  double max_angle = 0.0;
  for (uint32_t i = 0; i < 256; ++i) {
    const SampleRay r = view->sample(sample_2d(i, 3));
    EXPECT_TRUE(std::isinf(r.tfar));
    max_angle = std::max(max_angle, std::acos(std::min(1.0, static_cast<double>(r.dir.y))));
  }
  EXPECT_LE(max_angle, 0.00465 + 1e-4);
  EXPECT_GT(max_angle, 0.0035);  // the samples reach out toward the rim
  // Inside a sphere light there is no cap; a light without extent is punctual.
  const SampledLight sphere = make_sampled_light(sphere_light({0, 0, 0}, 1.0f), glm::dvec3(0.0));
  EXPECT_FALSE(LightView::create(sphere, glm::vec3(0.5f, 0.0f, 0.0f)));
  EXPECT_EQ(make_sampled_light(test::point_light({0, 1, 0}, 1.0f), glm::dvec3(0.0)).shape,
            SampledLight::Shape::kPunctual);
}

TEST(SoftVisibility, QuantizeAndGrayRoundTrip) {
  for (uint32_t levels : {2u, 4u, 8u, 16u, 256u}) {
    EXPECT_EQ(quantize(0.0f, levels), 0u);
    EXPECT_EQ(quantize(1.0f, levels), levels - 1);
    EXPECT_EQ(quantize(-0.5f, levels), 0u);
    EXPECT_EQ(quantize(1.5f, levels), levels - 1);
    EXPECT_EQ(quantize(std::nanf(""), levels), 0u);
    for (uint32_t l = 0; l < levels; ++l) {
      EXPECT_EQ(quantize(dequantize(l, levels), levels), l);
      EXPECT_EQ(gray_decode(gray_encode(l)), l);
      EXPECT_LT(gray_encode(l), levels);  // fits the same bits
      if (l > 0) {
        EXPECT_EQ(std::bitset<32>(gray_encode(l) ^ gray_encode(l - 1)).count(), 1u);
      }
    }
    // Worst error of a quantized fraction: half a step.
    for (int i = 0; i <= 1000; ++i) {
      const float f = static_cast<float>(i) / 1000.0f;
      EXPECT_LE(std::fabs(dequantize(quantize(f, levels), levels) - f), 0.5f / static_cast<float>(levels - 1) + 1e-6f);
    }
  }
}

}  // namespace
}  // namespace dhr::server
