// The shared light math (shaders/light_eval.h via scene/lighting.hpp): direction/distance, the
// "can contribute" test, glTF falloff, packing, per-view culling.
#include "scene/lighting.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <cstring>

namespace dhr {
namespace {

SceneLight make_point(glm::vec3 position, float intensity, float range = 0.0f) {
  SceneLight l;
  l.type = SceneLight::Type::kPoint;
  l.position = position;
  l.intensity = intensity;
  l.range = range;
  return l;
}

SceneLight make_spot(glm::vec3 position, glm::vec3 direction, float inner_deg, float outer_deg) {
  SceneLight l;
  l.type = SceneLight::Type::kSpot;
  l.position = position;
  l.direction = glm::normalize(direction);
  l.intensity = 8.0f;
  l.inner_cone = glm::radians(inner_deg);
  l.outer_cone = glm::radians(outer_deg);
  return l;
}

const glm::vec3 kUp(0.0f, 1.0f, 0.0f);

TEST(Lighting, PackedLayoutMatchesGlsl) {
  static_assert(sizeof(PackedLight) == 64);
  static_assert(offsetof(PackedLight, direction_range) == 16);
  static_assert(offsetof(PackedLight, color_intensity) == 32);
  static_assert(offsetof(PackedLight, spot) == 48);
  SceneLight l = make_spot({1, 2, 3}, {0, -1, 0}, 10.0f, 30.0f);
  l.color = {0.5f, 0.25f, 1.0f};
  l.range = 7.0f;
  const PackedLight p = pack_light(l, glm::dvec3(1.0, 1.0, 1.0));
  EXPECT_EQ(glm::vec3(p.position_type), glm::vec3(0, 1, 2));
  EXPECT_EQ(p.position_type.w, light_eval::kLightTypeSpot);
  EXPECT_EQ(glm::vec3(p.direction_range), glm::vec3(0, -1, 0));
  EXPECT_EQ(p.direction_range.w, 7.0f);
  EXPECT_EQ(p.color_intensity, glm::vec4(0.5f, 0.25f, 1.0f, 8.0f));
  EXPECT_NEAR(p.spot.x, std::cos(glm::radians(30.0f)), 1e-6);
}

TEST(Lighting, PackingKeepsPrecisionNearTheOrigin) {
  // A light 5 km away, packed relative to a point 1 m from it: the float result is exact to the micrometre.
  const SceneLight l = make_point({5000.25f, 0.0f, 0.0f}, 1.0f);
  const PackedLight p = pack_light(l, glm::dvec3(4999.0, 0.0, 0.0));
  EXPECT_FLOAT_EQ(p.position_type.x, 1.25f);
}

TEST(Lighting, PointLightDirectionDistanceAndFalloff) {
  const PackedLight p = pack_light(make_point({0, 2, 0}, 10.0f));
  const LightSample s = sample_light(p, glm::vec3(0.0f), kUp);
  EXPECT_EQ(s.test, LightTest::kContributes);
  EXPECT_FLOAT_EQ(s.distance, 2.0f);
  EXPECT_EQ(s.l, kUp);
  // E = I / d^2 (no range); N.L = 1.
  EXPECT_FLOAT_EQ(light_eval::light_attenuation(p, s.l, s.distance), 0.25f);
  const glm::vec3 c = light_contribution(p, s, kUp);
  EXPECT_FLOAT_EQ(c.x, 2.5f);
  // At 60 degrees: half the cosine.
  const glm::vec3 tilted(std::sin(glm::radians(60.0f)), std::cos(glm::radians(60.0f)), 0.0f);
  EXPECT_NEAR(light_contribution(p, s, tilted).x, 1.25f, 1e-5);
}

TEST(Lighting, BackfacingWhenNDotLIsNotPositive) {
  const PackedLight p = pack_light(make_point({0, 2, 0}, 10.0f));
  EXPECT_EQ(sample_light(p, glm::vec3(0.0f), -kUp).test, LightTest::kBackfacing);
  EXPECT_EQ(sample_light(p, glm::vec3(0.0f), glm::vec3(1, 0, 0)).test, LightTest::kBackfacing);  // N.L == 0
  EXPECT_EQ(light_contribution(p, sample_light(p, glm::vec3(0.0f), -kUp), -kUp), glm::vec3(0.0f));
}

TEST(Lighting, RangeWindowIsSmoothAndStrict) {
  const PackedLight p = pack_light(make_point({0, 0, 0}, 1.0f, 4.0f));
  const glm::vec3 n(0, 0, 1);
  EXPECT_EQ(sample_light(p, {0, 0, -3.99f}, n).test, LightTest::kContributes);
  EXPECT_EQ(sample_light(p, {0, 0, -4.0f}, n).test, LightTest::kOutOfRange);
  EXPECT_EQ(sample_light(p, {0, 0, -5.0f}, n).test, LightTest::kOutOfRange);
  // glTF window: (1 - (d/r)^4)^2 / d^2; at d = 2: (1 - 1/16)^2 / 4.
  const LightSample s = sample_light(p, {0, 0, -2.0f}, n);
  EXPECT_NEAR(light_eval::light_attenuation(p, s.l, s.distance), (15.0 / 16.0) * (15.0 / 16.0) / 4.0, 1e-6);
  // Continuous at the range: tends to zero.
  const LightSample near_edge = sample_light(p, {0, 0, -3.999f}, n);
  EXPECT_LT(light_eval::light_attenuation(p, near_edge.l, near_edge.distance), 1e-5f);
  // A point at the light cannot be lit by it (no direction).
  EXPECT_EQ(sample_light(p, glm::vec3(0.0f), n).test, LightTest::kOutOfRange);
}

TEST(Lighting, SpotConeAndAngularFalloff) {
  const PackedLight p = pack_light(make_spot({0, 1, 0}, {0, -1, 0}, 20.0f, 40.0f));
  auto at_angle = [&](float deg) {
    return glm::vec3(std::tan(glm::radians(deg)), 0.0f, 0.0f);  // floor point seen at `deg` off the axis
  };
  for (float deg : {0.0f, 10.0f, 19.9f}) {
    const LightSample s = sample_light(p, at_angle(deg), kUp);
    ASSERT_EQ(s.test, LightTest::kContributes) << deg;
    const float d2 = s.distance * s.distance;
    EXPECT_NEAR(light_eval::light_attenuation(p, s.l, s.distance) * d2, 1.0f, 1e-4) << deg;  // inside inner cone
  }
  const LightSample mid = sample_light(p, at_angle(30.0f), kUp);
  ASSERT_EQ(mid.test, LightTest::kContributes);
  const float a = light_eval::light_attenuation(p, mid.l, mid.distance) * mid.distance * mid.distance;
  const double c30 = std::cos(glm::radians(30.0)), c20 = std::cos(glm::radians(20.0)), c40 = std::cos(glm::radians(40.0));
  const double t = (c30 - c40) / (c20 - c40);
  EXPECT_NEAR(a, t * t, 1e-4);
  EXPECT_EQ(sample_light(p, at_angle(40.5f), kUp).test, LightTest::kOutOfRange);
  EXPECT_EQ(sample_light(p, at_angle(60.0f), kUp).test, LightTest::kOutOfRange);
  // Out of range takes precedence over back-facing.
  EXPECT_EQ(sample_light(p, at_angle(60.0f), -kUp).test, LightTest::kOutOfRange);
}

TEST(Lighting, DirectionalLightIsIntensityTimesColour) {
  SceneLight l;
  l.type = SceneLight::Type::kDirectional;
  l.direction = glm::normalize(glm::vec3(0, -1, -1));
  l.intensity = 3.0f;
  l.color = {1.0f, 0.5f, 0.0f};
  l.range = 2.0f;  // ignored for directional lights
  const PackedLight p = pack_light(l);
  const LightSample s = sample_light(p, glm::vec3(1000.0f, 0.0f, 0.0f), kUp);
  EXPECT_EQ(s.test, LightTest::kContributes);
  EXPECT_EQ(s.distance, light_eval::kLightInfiniteDistance);
  EXPECT_NEAR(glm::length(s.l - glm::normalize(glm::vec3(0, 1, 1))), 0.0f, 1e-6);
  EXPECT_EQ(light_eval::light_irradiance(p, s.l, s.distance), glm::vec3(3.0f, 1.5f, 0.0f));
  EXPECT_EQ(sample_light(p, glm::vec3(0.0f), -kUp).test, LightTest::kBackfacing);
}

// A 0.8 x 0.5 m rect light at (0, 2, 0) facing down, 50 nits: 20 cd along its normal.
SceneLight make_rect() {
  SceneLight l;
  l.type = SceneLight::Type::kRect;
  l.position = {0, 2, 0};
  l.direction = {0, -1, 0};
  l.tangent = {1, 0, 0};
  l.bitangent = {0, 0, -1};
  l.intensity = 50.0f;
  l.width = 0.8f;
  l.height = 0.5f;
  return l;
}

TEST(Lighting, RectAndDiskPackAsNitsTimesArea) {
  const PackedLight rect = pack_light(make_rect(), glm::dvec3(0.0, 1.0, 0.0));
  EXPECT_EQ(rect.position_type, glm::vec4(0, 1, 0, light_eval::kLightTypeRect));
  EXPECT_EQ(glm::vec3(rect.direction_range), glm::vec3(0, -1, 0));
  EXPECT_FLOAT_EQ(rect.color_intensity.w, 20.0f);  // 50 nits x 0.4 m^2
  EXPECT_TRUE(light_eval::light_is_area(rect));
  EXPECT_FALSE(light_eval::light_is_directional(rect));
  EXPECT_FALSE(light_eval::light_is_spot(rect));
  SceneLight disk = make_rect();
  disk.type = SceneLight::Type::kDisk;
  disk.height = disk.width;
  const PackedLight d = pack_light(disk);
  EXPECT_EQ(d.position_type.w, light_eval::kLightTypeDisk);
  EXPECT_NEAR(d.color_intensity.w, 50.0 * M_PI * 0.16, 1e-4);  // pi r^2, r = 0.4
  EXPECT_TRUE(light_eval::light_is_area(d));
  EXPECT_FALSE(light_eval::light_is_directional(d));
}

// Sphere lights and the sun disk shade exactly as their punctual light (their extent only softens shadows).
TEST(Lighting, SphereAndSunPackAsTheirPunctualLight) {
  SceneLight sphere = make_point({1, 2, 3}, 8.0f, 5.0f);
  const PackedLight punctual = pack_light(sphere);
  sphere.radius = 0.06f;
  const PackedLight packed = pack_light(sphere);
  EXPECT_EQ(std::memcmp(&packed, &punctual, sizeof packed), 0);
  SceneLight sun;
  sun.type = SceneLight::Type::kDirectional;
  sun.direction = {0, -1, 0};
  const PackedLight sun_punctual = pack_light(sun);
  sun.angle = 0.0093f;
  const PackedLight sun_packed = pack_light(sun);
  EXPECT_EQ(std::memcmp(&sun_packed, &sun_punctual, sizeof sun_packed), 0);
}

// One-sided: nothing behind the emitter's plane (kOutOfRange, like outside a spot's cone); in front, a point light
// at the centre whose intensity falls off with the cosine between the emission normal and the direction to the point.
TEST(Lighting, RectLightIsZeroBehindAndCosineWeightedInFront) {
  const PackedLight p = pack_light(make_rect());
  // Straight below, 2 m: E = 20 cd / 4 m^2.
  const LightSample below = sample_light(p, glm::vec3(0.0f), kUp);
  ASSERT_EQ(below.test, LightTest::kContributes);
  EXPECT_FLOAT_EQ(light_contribution(p, below, kUp).x, 5.0f);
  // 60 degrees off the normal (a wall point facing the light): cos 60 = 0.5 of the intensity.
  const glm::vec3 q(2.0f * std::tan(glm::radians(60.0f)), 0.0f, 0.0f);
  const LightSample off = sample_light(p, q, kUp);
  ASSERT_EQ(off.test, LightTest::kContributes);
  EXPECT_NEAR(light_eval::light_attenuation(p, off.l, off.distance) * off.distance * off.distance, 0.5f, 1e-5);
  // Above the emitter (behind it) and in its plane: nothing, even for a surface that faces the light.
  for (const glm::vec3& behind : {glm::vec3(0, 3, 0), glm::vec3(1, 3, 1), glm::vec3(3, 2, 0)}) {
    const LightSample s = sample_light(p, behind, -kUp);
    EXPECT_EQ(s.test, LightTest::kOutOfRange);
    EXPECT_EQ(light_contribution(p, s, -kUp), glm::vec3(0.0f));
    EXPECT_EQ(light_eval::light_attenuation(p, s.l, s.distance), 0.0f);
  }
  // Back-facing surfaces in front of it are back-facing, as for a point light.
  EXPECT_EQ(sample_light(p, glm::vec3(0.0f), -kUp).test, LightTest::kBackfacing);
}

Camera forward_camera() {
  Camera c;  // at the origin looking down -Z, 90 x 90 degrees
  c.tangents = Tangents{-1.0, 1.0, 1.0, -1.0};
  c.extent = Extent{100, 100};
  return c;
}

TEST(Lighting, CullsOnlyLightsWhoseRangeMissesTheFrustum) {
  const Camera cam = forward_camera();
  EXPECT_TRUE(light_may_reach_view(make_point({0, 0, -5}, 1.0f, 1.0f), cam));     // in view
  EXPECT_FALSE(light_may_reach_view(make_point({0, 0, 5}, 1.0f, 1.0f), cam));     // behind
  EXPECT_TRUE(light_may_reach_view(make_point({0, 0, 0.5f}, 1.0f, 1.0f), cam));   // behind, range reaches
  EXPECT_TRUE(light_may_reach_view(make_point({0, 0, 5}, 1.0f, 0.0f), cam));      // infinite range
  EXPECT_FALSE(light_may_reach_view(make_point({-10, 0, -1}, 1.0f, 2.0f), cam));  // far left
  EXPECT_TRUE(light_may_reach_view(make_point({-10, 0, -1}, 1.0f, 7.0f), cam));   // ... with a long range
  EXPECT_FALSE(light_may_reach_view(make_point({0, 20, -2}, 1.0f, 5.0f), cam));   // far above
  SceneLight sun;
  sun.type = SceneLight::Type::kDirectional;
  sun.range = 1.0f;
  EXPECT_TRUE(light_may_reach_view(sun, cam));
  // The camera's pose is respected: turned around, the light behind is now in front.
  Camera turned = cam;
  turned.T_world_eye.orientation = glm::angleAxis(3.14159265358979, glm::dvec3(0, 1, 0));
  EXPECT_TRUE(light_may_reach_view(make_point({0, 0, 5}, 1.0f, 1.0f), turned));
  EXPECT_FALSE(light_may_reach_view(make_point({0, 0, -5}, 1.0f, 1.0f), turned));
}

TEST(Lighting, CullingIsConservativeAtTheBoundary) {
  const Camera cam = forward_camera();
  // Sphere just touching the left plane x = -depth (distance to the plane = 7.07 - tiny): kept.
  const float r = static_cast<float>(10.0 / std::sqrt(2.0));
  EXPECT_TRUE(light_may_reach_view(make_point({-10.0f, 0.0f, 0.0f}, 1.0f, r + 1e-3f), cam));
  EXPECT_TRUE(light_may_reach_view(make_point({-10.0f, 0.0f, 0.0f}, 1.0f, r), cam));
  EXPECT_FALSE(light_may_reach_view(make_point({-10.0f, 0.0f, 0.0f}, 1.0f, r * 0.99f), cam));
}

}  // namespace
}  // namespace dhr
