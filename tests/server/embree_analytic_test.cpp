// The Embree tracer against analytic answers on hand-made scenes: a floor with a floating box and
// point / directional / spot / rect lights, range cut-off, back-facing lights, single/double-sided surfaces.
// Pixels whose answer changes within a small margin (silhouettes, shadow boundaries) are not checked.
#include "trace/embree/embree_tracer.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <functional>

namespace dhr::server {
namespace {

using test::add_box;
using test::add_grid;
using test::finalize;

const glm::dvec3 kBoxMin(-0.5, 0.5, -0.5), kBoxMax(0.5, 1.5, 0.5);
constexpr double kFloorHalf = 10.0;
constexpr double kMargin = 0.02;  // metres: closer to a boundary than this is not checked

TracerOptions tracer_options(SkipOptions skip = {}) {
  TracerOptions o;
  o.threads = 2;
  o.skip = skip;
  return o;
}

// Floor y = 0 (20 x 20 m, 8 x 8 cells, facing up) and a closed box floating above it.
Scene floor_and_box(std::vector<SceneLight> lights, bool with_box = true) {
  Scene scene = test::make_empty_scene();
  add_grid(scene, {-kFloorHalf, 0, kFloorHalf}, {2 * kFloorHalf, 0, 0}, {0, 0, -2 * kFloorHalf}, 8, test::kSingleSided);
  if (with_box) add_box(scene, glm::vec3(kBoxMin), glm::vec3(kBoxMax), test::kSingleSided);
  scene.lights = std::move(lights);
  finalize(scene);
  return scene;
}

// Tri-state: definitely 1, definitely 0, or too close to call.
enum class Expect { kLit, kDark, kSkip };

struct FloorCheck {
  int checked_lit = 0;
  int checked_dark = 0;
  int mismatches = 0;
};

// For every pixel whose primary ray certainly hits the floor (not the box, not near the floor's edge),
// compares bit 0 with expect(p) for the floor point p.
FloorCheck check_floor(const Camera& camera, const VisibilityBuffer& vis, bool with_box,
                       const std::function<Expect(const glm::dvec3&)>& expect) {
  FloorCheck out;
  const glm::dvec3 grow(kMargin), o = camera.T_world_eye.position;
  for (uint32_t y = 0; y < camera.extent.height; ++y) {
    for (uint32_t x = 0; x < camera.extent.width; ++x) {
      const glm::dvec3 d = camera.world_ray(x + 0.5, y + 0.5);
      if (!(d.y < 0.0)) continue;
      const glm::dvec3 p = o + d * (-o.y / d.y);
      if (std::fabs(p.x) > kFloorHalf - kMargin || std::fabs(p.z) > kFloorHalf - kMargin) continue;
      if (with_box && test::ray_box(o, d, kBoxMin - grow, kBoxMax + grow)) continue;
      const Expect e = expect(p);
      if (e == Expect::kSkip) continue;
      const bool bit = (vis.get(x, y) & 1u) != 0;
      (e == Expect::kLit ? out.checked_lit : out.checked_dark)++;
      if (bit != (e == Expect::kLit)) {
        if (out.mismatches < 5) ADD_FAILURE() << "pixel " << x << "," << y << " floor point " << p.x << "," << p.z;
        ++out.mismatches;
      }
    }
  }
  return out;
}

// Occlusion of segment p -> q by the box, with the margin: kSkip when growing/shrinking the box flips it.
Expect box_shadow(const glm::dvec3& p, const glm::dvec3& q) {
  const glm::dvec3 m(kMargin);
  const bool big = test::segment_hits_box(p, q, kBoxMin - m, kBoxMax + m);
  const bool small = test::segment_hits_box(p, q, kBoxMin + m, kBoxMax - m);
  if (big != small) return Expect::kSkip;
  return big ? Expect::kDark : Expect::kLit;
}

TEST(EmbreeAnalytic, PointLightShadowOfABox) {
  const glm::dvec3 light(0.3, 4.0, 0.2);
  const Scene scene = floor_and_box({test::point_light(glm::vec3(light), 50.0f)});
  EmbreeTracer tracer(scene, tracer_options());
  const Camera camera = test::look_camera({0.0, 6.0, 6.0}, {0.0, 0.0, 0.0}, 200, 150);
  VisibilityBuffer vis;
  TraceStats stats;
  tracer.trace(camera, vis, stats);
  const FloorCheck r = check_floor(camera, vis, true, [&](const glm::dvec3& p) { return box_shadow(p, light); });
  EXPECT_EQ(r.mismatches, 0);
  EXPECT_GT(r.checked_dark, 100);
  EXPECT_GT(r.checked_lit, 1000);

  // The box itself: its top faces the light (lit), its sides and bottom face away (N.L <= 0: dark).
  int top = 0, sides = 0;
  const glm::dvec3 m(kMargin);
  for (uint32_t y = 0; y < camera.extent.height; ++y) {
    for (uint32_t x = 0; x < camera.extent.width; ++x) {
      const glm::dvec3 o = camera.T_world_eye.position, d = camera.world_ray(x + 0.5, y + 0.5);
      if (!test::ray_box(o, d, kBoxMin + m, kBoxMax - m)) continue;  // certainly on the box
      const glm::dvec3 p = o + d * *test::ray_box(o, d, kBoxMin, kBoxMax);
      const bool bit = vis.get(x, y) & 1u;
      if (std::fabs(p.y - kBoxMax.y) < 1e-6) {
        if (std::fabs(p.x) > 0.5 - kMargin || std::fabs(p.z) > 0.5 - kMargin) continue;
        EXPECT_TRUE(bit) << x << "," << y;
        ++top;
      } else {
        EXPECT_FALSE(bit) << x << "," << y;
        ++sides;
      }
    }
  }
  EXPECT_GT(top, 20);
  EXPECT_GT(sides, 20);
  // Every hit pixel's pair is accounted for exactly once.
  const uint64_t hit = stats.pixels - stats.background_pixels;
  EXPECT_EQ(stats.shadow_rays + stats.skipped_backfacing + stats.skipped_out_of_range + stats.skipped_culled_light,
            hit * 1);
  EXPECT_EQ(stats.primary_rays, stats.pixels);
  EXPECT_GT(stats.skipped_backfacing, 0u);
}

TEST(EmbreeAnalytic, DirectionalLightShadowOfABox) {
  const glm::dvec3 dir = glm::normalize(glm::dvec3(0.4, -1.0, 0.25));
  const Scene scene = floor_and_box({test::directional_light(glm::vec3(dir))});
  EmbreeTracer tracer(scene, tracer_options());
  const Camera camera = test::look_camera({-2.0, 5.0, 5.0}, {0.5, 0.0, 0.0}, 200, 150);
  VisibilityBuffer vis;
  TraceStats stats;
  tracer.trace(camera, vis, stats);
  const FloorCheck r = check_floor(camera, vis, true, [&](const glm::dvec3& p) { return box_shadow(p, p - dir * 100.0); });
  EXPECT_EQ(r.mismatches, 0);
  EXPECT_GT(r.checked_dark, 100);
  EXPECT_GT(r.checked_lit, 1000);
}

TEST(EmbreeAnalytic, SpotConeLimitsTheLitRegion) {
  const glm::dvec3 pos(0.0, 3.0, 0.0);
  const Scene scene = floor_and_box({test::spot_light(glm::vec3(pos), {0.0f, -1.0f, 0.0f}, 15.0f, 30.0f)}, false);
  EmbreeTracer tracer(scene, tracer_options());
  const Camera camera = test::look_camera({0.0, 5.0, 4.0}, {0.0, 0.0, 0.0}, 160, 120);
  VisibilityBuffer vis;
  TraceStats stats;
  tracer.trace(camera, vis, stats);
  const FloorCheck r = check_floor(camera, vis, false, [&](const glm::dvec3& p) {
    const double angle = glm::degrees(std::acos(glm::dot(glm::normalize(p - pos), glm::dvec3(0, -1, 0))));
    if (std::fabs(angle - 30.0) < 0.5) return Expect::kSkip;
    return angle < 30.0 ? Expect::kLit : Expect::kDark;
  });
  EXPECT_EQ(r.mismatches, 0);
  EXPECT_GT(r.checked_dark, 100);
  EXPECT_GT(r.checked_lit, 100);
  EXPECT_GT(stats.skipped_out_of_range, 0u);  // outside the cone: no ray
}

// A rect light is one-sided (nothing behind its plane, and no ray: kOutOfRange) and, for hard shadows, a point at
// its centre: tilted 45 degrees towards +X above the floor, it lights the floor where x > -3, minus the box's shadow.
TEST(EmbreeAnalytic, RectLightIsOneSidedAndShadowsFromItsCentre) {
  const glm::dvec3 pos(0.0, 3.0, 0.0), dir = glm::normalize(glm::dvec3(1.0, -1.0, 0.0));
  SceneLight rect;
  rect.type = SceneLight::Type::kRect;
  rect.position = glm::vec3(pos);
  rect.direction = glm::vec3(dir);
  rect.tangent = glm::vec3(glm::normalize(glm::dvec3(1.0, 1.0, 0.0)));
  rect.bitangent = glm::cross(rect.tangent, rect.direction);
  rect.intensity = 100.0f;
  rect.width = 1.0f;
  rect.height = 0.5f;
  ASSERT_FALSE(validate_light(rect).has_value());
  const Scene scene = floor_and_box({rect});
  EmbreeTracer tracer(scene, tracer_options());
  const Camera camera = test::look_camera({0.0, 7.0, 7.0}, {0.0, 0.0, 0.0}, 200, 150, 100.0);
  VisibilityBuffer vis;
  TraceStats stats;
  tracer.trace(camera, vis, stats);
  const FloorCheck r = check_floor(camera, vis, true, [&](const glm::dvec3& p) {
    const double in_front = glm::dot(p - pos, dir);
    if (std::fabs(in_front) < kMargin) return Expect::kSkip;
    return in_front < 0.0 ? Expect::kDark : box_shadow(p, pos);
  });
  EXPECT_EQ(r.mismatches, 0);
  EXPECT_GT(r.checked_dark, 1000);  // behind the emitter
  EXPECT_GT(r.checked_lit, 1000);
  EXPECT_GT(stats.skipped_out_of_range, 0u);  // behind it: no ray
}

TEST(EmbreeAnalytic, RangeCutsOffPointLight) {
  const glm::dvec3 pos(0.0, 2.0, 0.0);
  const Scene scene = floor_and_box({test::point_light(glm::vec3(pos), 10.0f, 4.0f)}, false);
  EmbreeTracer tracer(scene, tracer_options());
  const Camera camera = test::look_camera({0.0, 6.0, 6.0}, {0.0, 0.0, 0.0}, 160, 120);
  VisibilityBuffer vis;
  TraceStats stats;
  tracer.trace(camera, vis, stats);
  const FloorCheck r = check_floor(camera, vis, false, [&](const glm::dvec3& p) {
    const double dist = glm::length(p - pos);
    if (std::fabs(dist - 4.0) < kMargin) return Expect::kSkip;
    return dist < 4.0 ? Expect::kLit : Expect::kDark;
  });
  EXPECT_EQ(r.mismatches, 0);
  EXPECT_GT(r.checked_dark, 100);
  EXPECT_GT(r.checked_lit, 100);
  EXPECT_GT(stats.skipped_out_of_range, 0u);
}

TEST(EmbreeAnalytic, LightBehindTheSurfaceGivesZeroWithoutRays) {
  const Scene scene = floor_and_box({test::point_light({0.0f, -2.0f, 0.0f}, 10.0f)}, false);
  const Camera camera = test::look_camera({0.0, 6.0, 6.0}, {0.0, 0.0, 0.0}, 120, 90);
  for (const SkipOptions skip : {SkipOptions{}, SkipOptions::none()}) {
    EmbreeTracer tracer(scene, tracer_options(skip));
    VisibilityBuffer vis;
    TraceStats stats;
    tracer.trace(camera, vis, stats);
    const uint64_t hit = stats.pixels - stats.background_pixels;
    ASSERT_GT(hit, 1000u);
    for (size_t i = 0; i < vis.pixel_count(); ++i) ASSERT_EQ(vis.mask_at(i), 0u) << i;
    if (skip.backfacing) {
      EXPECT_EQ(stats.skipped_backfacing, hit);
      EXPECT_EQ(stats.shadow_rays, 0u);
    } else {
      EXPECT_EQ(stats.shadow_rays, hit);
      EXPECT_EQ(stats.skipped_backfacing, 0u);
    }
  }
}

TEST(EmbreeAnalytic, SingleSidedBackFacesAreInvisibleToPrimaryRays) {
  // A floor seen from below: single-sided -> background; double-sided -> hit, normal flipped to the viewer.
  const Camera camera = test::look_camera({0.0, -3.0, 3.0}, {0.0, 0.0, 0.0}, 64, 48);
  for (uint32_t material : {test::kSingleSided, test::kDoubleSided}) {
    Scene scene = test::make_empty_scene();
    add_grid(scene, {-5, 0, 5}, {10, 0, 0}, {0, 0, -10}, 4, material);
    scene.lights = {test::point_light({0.0f, -1.0f, 0.0f}, 10.0f), test::point_light({0.0f, 1.0f, 0.0f}, 10.0f)};
    finalize(scene);
    EmbreeTracer tracer(scene, tracer_options());
    VisibilityBuffer vis;
    TraceStats stats;
    tracer.trace(camera, vis, stats);
    const glm::dvec3 centre_dir = camera.world_ray(32.0, 24.0);
    ASSERT_GT(centre_dir.y, 0.0);  // looking up at the floor's underside
    if (material == test::kSingleSided) {
      EXPECT_EQ(stats.background_pixels, stats.pixels);
    } else {
      EXPECT_LT(stats.background_pixels, stats.pixels / 2);
      EXPECT_EQ(vis.get(32, 24), 1u);  // the light below (viewer's side) is visible, the one above is not
    }
    // Shadow rays see both sides: a single-sided floor between a point and a light still occludes.
    const EmbreeScene& es = tracer.embree_scene();
    EXPECT_TRUE(es.occluded(es.to_relative({0.0, -1.0, 0.0}), {0.0f, 1.0f, 0.0f}, 2.0f));
    EXPECT_TRUE(es.occluded(es.to_relative({0.0, 1.0, 0.0}), {0.0f, -1.0f, 0.0f}, 2.0f));
  }
}

TEST(EmbreeAnalytic, BackgroundPixelsAreZeroAndCounted) {
  const Scene scene = floor_and_box({test::directional_light({0.0f, -1.0f, 0.0f})});
  EmbreeTracer tracer(scene, tracer_options());
  const Camera camera = test::look_camera({0.0, 1.0, 20.0}, {0.0, 3.0, 0.0}, 80, 60);  // mostly sky
  VisibilityBuffer vis;
  TraceStats stats;
  tracer.trace(camera, vis, stats);
  EXPECT_GT(stats.background_pixels, stats.pixels / 3);
  EXPECT_EQ(stats.shadow_rays + stats.skipped_backfacing + stats.skipped_out_of_range,
            stats.pixels - stats.background_pixels);
  for (uint32_t y = 0; y < 60; ++y)
    for (uint32_t x = 0; x < 80; ++x)
      if (camera.world_ray(x + 0.5, y + 0.5).y > 0.05) {
        ASSERT_EQ(vis.get(x, y), 0u);
      }
}

}  // namespace
}  // namespace dhr::server
