// Samples over a light's extent as seen from one surface point, for fractional (soft) visibility.
//
// What is sampled, per shape (SceneLight's extent, scene.hpp):
//   sphere light (point/spot with radius): directions uniform in the solid angle of the cap the sphere covers
//     (cone sampling; pdf = 1 / (2 pi (1 - cos theta_max))); each ray ends at the sphere's near surface.
//   disk sun (directional with angle): directions uniform in the cone of half-angle angle/2 around the
//     direction toward the sun; rays are unbounded.
//   rect, disk (one-sided emitters): points uniform over the emitter's area; each ray ends at that point.
//   anything without an extent: one sample, the hard tracer's ray (embree_trace_tile.hpp's make_shadow_ray).
// The 2D sample points are an Owen-scrambled Sobol (0,2)-sequence: every prefix of 2^k points is stratified
// in every 2^a x 2^b grid with a + b = k, so the first 4 already cover the light's four quadrants and any
// power-of-two prefix is a stratified estimate. The scramble seed is an integer hash of (pixel, light, salt):
// integer arithmetic only, so the same inputs give the same bits on every run and machine with the same libm.
#pragma once
#include "scene/lighting.hpp"
#include "scene/scene.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>

namespace dhr::server {

// A 32-bit integer hash with good avalanche (Wellons' "lowbias32").
uint32_t hash_u32(uint32_t x);
// The scramble seed of one pixel and light; `salt` selects an independent scramble (e.g. a reference run, or a
// later frame when soft shadows converge over frames).
uint32_t soft_seed(uint32_t x, uint32_t y, uint32_t light, uint32_t salt = 0);
// Point `index` of the sequence scrambled by `seed`, in [0, 1)^2 (24-bit fixed point: exact floats).
glm::vec2 sample_2d(uint32_t index, uint32_t seed);

// A light prepared for sampling, in the scene's relative frame (EmbreeScene::origin()).
struct SampledLight {
  enum class Shape : uint8_t { kPunctual, kSphere, kSunDisk, kRect, kDisk };
  Shape shape = Shape::kPunctual;
  PackedLight packed{};           // the whole-light test (light_eval at the centre) and the punctual ray
  glm::dvec3 centre{0.0};         // sphere, rect, disk
  glm::dvec3 direction{0.0};      // unit, where the light travels (sun, rect, disk)
  double radius = 0.0;            // sphere
  double sun_one_minus_cos = 0.0; // sun: 1 - cos(angle / 2), computed without cancellation
  glm::dvec3 half_u{0.0};         // rect: tangent * width / 2; disk: tangent * width / 2 (a radius vector)
  glm::dvec3 half_v{0.0};         // rect: bitangent * height / 2; disk: bitangent * height / 2
  bool one_sided() const { return shape == Shape::kRect || shape == Shape::kDisk; }
};

// `origin`: the world position of the relative frame. A light whose extent is zero (or invalid: negative,
// non-finite) is kPunctual; a rect or disk without area keeps its one-sidedness but is sampled as a point.
SampledLight make_sampled_light(const SceneLight& light, const glm::dvec3& origin);

// A sample point u of the sequence with what every surface point would compute from it alone, once: the emitter's
// point in [-1, 1]^2 (rect: 2u - 1; disk: the concentric map) or the cone's azimuth (cos, sin of 2 pi u.y). With
// one scramble per light (SoftPattern::kPerLight) every pixel samples the same points, so a batch prepares them
// once per light instead of once per pair (soft_visibility.cpp). LightView::sample gives the same bits either way.
struct SamplePoint {
  glm::vec2 u{0.0f};
  glm::vec2 q{0.0f};
};
SamplePoint prepare_sample(SampledLight::Shape shape, glm::vec2 u);

// One sample ray: unit direction and where it ends (tfar, infinite for the sun).
struct SampleRay {
  glm::vec3 dir{0.0f, 1.0f, 0.0f};
  float tfar = 0.0f;
};

// What one ray origin sees of one (non-punctual) light: prepared once per surface point, sampled many times.
class LightView {
 public:
  // std::nullopt when the origin receives nothing from the light's extent: behind a one-sided emitter (or in
  // its plane), or inside a sphere light.
  static std::optional<LightView> create(const SampledLight& light, const glm::vec3& origin);
  // The ray of the sample point u in [0, 1)^2 (uniform in solid angle for cones, in area for emitters).
  SampleRay sample(glm::vec2 u) const { return sample(prepare_sample(shape_, u)); }
  // The same from a point prepared for this light's shape (prepare_sample): bit for bit the same ray.
  SampleRay sample(const SamplePoint& point) const;
  // Solid angle (steradians) the cone covers; 0 for area emitters. For tests and pdf bookkeeping.
  double cone_solid_angle() const;

 private:
  LightView() = default;
  // Set up in double once per view, sampled in float (the rays are float anyway): the per-sample arithmetic is a
  // large share of the soft trace's time (docs/server.md); float took 7 % off soft_bench's CPU time.
  SampledLight::Shape shape_ = SampledLight::Shape::kPunctual;
  glm::vec3 axis_{0.0f}, b1_{0.0f}, b2_{0.0f};  // cone frame (sphere, sun)
  float one_minus_cos_max_ = 0.0f;              // cone: 1 - cos(half-angle)
  glm::vec3 centre_{0.0f};                      // sphere, rect, disk: centre relative to the origin
  float sphere_c_ = 0.0f;                       // sphere: |centre|^2 - radius^2 (relative to the origin)
  glm::vec3 half_u_{0.0f}, half_v_{0.0f};       // rect, disk
};

}  // namespace dhr::server
