#include "trace/soft/light_sampler.hpp"
#include "trace/soft/soft_options.hpp"

#include "trace/embree/embree_trace_tile.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <numbers>

namespace dhr::server {
namespace {

uint32_t reverse_bits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
  x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
  return (x >> 16) | (x << 16);
}

// Nested uniform (Owen) scramble of a 32-bit fixed-point coordinate: Burley 2020, "Practical Hash-based Owen
// Scrambling" (JCGT 9(4)). Each bit is flipped by a hash of the bits above it, which keeps the net's strata.
uint32_t owen_scramble(uint32_t x, uint32_t seed) {
  x = reverse_bits(x);
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return reverse_bits(x);
}

// Sobol's second dimension (primitive polynomial x + 1): direction v_k = v_{k-1} ^ (v_{k-1} >> 1).
uint32_t sobol_dim1(uint32_t index) {
  uint32_t x = 0, v = 0x80000000u;
  for (; index != 0; index >>= 1, v ^= v >> 1)
    if (index & 1u) x ^= v;
  return x;
}

float to_unit(uint32_t x) { return static_cast<float>(x >> 8) * 0x1p-24f; }  // [0, 1), exact

// An orthonormal frame around unit n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
void basis(const glm::dvec3& n, glm::dvec3& b1, glm::dvec3& b2) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  b1 = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  b2 = glm::dvec3(b, sign + n.y * n.y * a, -n.y);
}

// Shirley-Chiu concentric map of [0,1)^2 onto the unit disk: area-preserving and keeps the strata compact.
glm::dvec2 concentric_disk(glm::vec2 u) {
  const double a = 2.0 * static_cast<double>(u.x) - 1.0, b = 2.0 * static_cast<double>(u.y) - 1.0;
  if (a == 0.0 && b == 0.0) return glm::dvec2(0.0);
  constexpr double kQuarterPi = std::numbers::pi / 4.0;
  if (std::fabs(a) > std::fabs(b)) {
    const double phi = kQuarterPi * (b / a);
    return a * glm::dvec2(std::cos(phi), std::sin(phi));
  }
  const double phi = 2.0 * kQuarterPi - kQuarterPi * (a / b);
  return b * glm::dvec2(std::cos(phi), std::sin(phi));
}

bool finite_positive(float v) { return std::isfinite(v) && v > 0.0f; }

}  // namespace

uint32_t hash_u32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

uint32_t soft_seed(uint32_t x, uint32_t y, uint32_t light, uint32_t salt) {
  return hash_u32(x ^ hash_u32(y ^ hash_u32(light ^ hash_u32(salt ^ 0x9e3779b9u))));
}

uint32_t SoftOptions::seed(uint32_t x, uint32_t y, uint32_t light) const {
  return pattern == SoftPattern::kPerPixel ? soft_seed(x, y, light, salt) : soft_seed(0, 0, light, salt);
}

glm::vec2 sample_2d(uint32_t index, uint32_t seed) {
  // Dimension 0 is the van der Corput sequence (the reversed index); each dimension has its own scramble.
  return glm::vec2(to_unit(owen_scramble(reverse_bits(index), hash_u32(seed))),
                   to_unit(owen_scramble(sobol_dim1(index), hash_u32(seed ^ 0x68bc21ebu))));
}

SampledLight make_sampled_light(const SceneLight& light, const glm::dvec3& origin) {
  SampledLight s;
  s.packed = pack_light(light, origin);
  s.centre = glm::dvec3(light.position) - origin;
  s.direction = glm::normalize(glm::dvec3(light.direction));
  using Type = SceneLight::Type;
  switch (light.type) {
    case Type::kPoint:
    case Type::kSpot:
      if (finite_positive(light.radius)) {
        s.shape = SampledLight::Shape::kSphere;
        s.radius = static_cast<double>(light.radius);
      }
      break;
    case Type::kDirectional:
      if (finite_positive(light.angle) && static_cast<double>(light.angle) < std::numbers::pi) {
        s.shape = SampledLight::Shape::kSunDisk;
        const double half = 0.5 * static_cast<double>(light.angle);
        s.sun_one_minus_cos = 2.0 * std::sin(0.5 * half) * std::sin(0.5 * half);  // 1 - cos, no cancellation
      }
      break;
    case Type::kRect:
    case Type::kDisk:
      s.shape = light.type == Type::kRect ? SampledLight::Shape::kRect : SampledLight::Shape::kDisk;
      // No area: a one-sided point (half extents 0), still sampled through the area path.
      s.half_u = glm::dvec3(light.tangent) * (finite_positive(light.width) ? 0.5 * static_cast<double>(light.width) : 0.0);
      s.half_v = glm::dvec3(light.bitangent) * (finite_positive(light.height) ? 0.5 * static_cast<double>(light.height) : 0.0);
      break;
  }
  return s;
}

std::optional<LightView> LightView::create(const SampledLight& light, const glm::vec3& origin) {
  LightView v;
  v.shape_ = light.shape;
  const glm::dvec3 o(origin);
  const glm::dvec3 to_centre = light.centre - o;
  v.centre_ = glm::vec3(to_centre);
  glm::dvec3 axis(0.0);
  double one_minus_cos_max = 0.0;
  switch (light.shape) {
    case SampledLight::Shape::kPunctual:
      return std::nullopt;  // the caller traces the hard ray
    case SampledLight::Shape::kSphere: {
      const double d = glm::length(to_centre);
      if (!(d > light.radius)) return std::nullopt;  // inside the sphere: no cap to sample
      axis = to_centre / d;
      const double sin_max = light.radius / d;
      const double sin2 = sin_max * sin_max;
      one_minus_cos_max = sin2 / (1.0 + std::sqrt(1.0 - sin2));  // 1 - cos, no cancellation for small caps
      v.sphere_c_ = static_cast<float>(glm::dot(to_centre, to_centre) - light.radius * light.radius);
      break;
    }
    case SampledLight::Shape::kSunDisk:
      axis = -light.direction;
      one_minus_cos_max = light.sun_one_minus_cos;
      break;
    case SampledLight::Shape::kRect:
    case SampledLight::Shape::kDisk:
      // One-sided: only points strictly in front of the emitter (on the side it emits to) receive light.
      if (!(glm::dot(-to_centre, light.direction) > 0.0)) return std::nullopt;
      v.half_u_ = glm::vec3(light.half_u);
      v.half_v_ = glm::vec3(light.half_v);
      return v;
  }
  glm::dvec3 b1, b2;
  basis(axis, b1, b2);
  v.axis_ = glm::vec3(axis);
  v.b1_ = glm::vec3(b1);
  v.b2_ = glm::vec3(b2);
  v.one_minus_cos_max_ = static_cast<float>(one_minus_cos_max);
  return v;
}

SamplePoint prepare_sample(SampledLight::Shape shape, glm::vec2 u) {
  SamplePoint p;
  p.u = u;
  switch (shape) {
    case SampledLight::Shape::kRect:
      p.q = 2.0f * u - 1.0f;
      break;
    case SampledLight::Shape::kDisk:
      p.q = glm::vec2(concentric_disk(u));
      break;
    case SampledLight::Shape::kSphere:
    case SampledLight::Shape::kSunDisk: {
      const float phi = 2.0f * std::numbers::pi_v<float> * u.y;
      p.q = glm::vec2(std::cos(phi), std::sin(phi));
      break;
    }
    case SampledLight::Shape::kPunctual:
      break;
  }
  return p;
}

SampleRay LightView::sample(const SamplePoint& point) const {
  SampleRay ray;
  const glm::vec2 u = point.u, q = point.q;
  if (shape_ == SampledLight::Shape::kRect || shape_ == SampledLight::Shape::kDisk) {
    const glm::vec3 d = centre_ + q.x * half_u_ + q.y * half_v_;
    const float dist = glm::length(d);
    ray.dir = d / dist;
    ray.tfar = dist * detail::kShadowTfarScale;  // the emitter's own surface is no occluder
    return ray;
  }
  // Uniform in the cone's solid angle: 1 - cos(theta) uniform in [0, 1 - cos_max), phi uniform.
  const float om = u.x * one_minus_cos_max_;
  const float sin_theta = std::sqrt(std::max(0.0f, om * (2.0f - om)));
  ray.dir = glm::normalize((1.0f - om) * axis_ + sin_theta * (q.x * b1_ + q.y * b2_));  // q: cos, sin of phi
  if (shape_ == SampledLight::Shape::kSunDisk) {
    ray.tfar = std::numeric_limits<float>::infinity();
    return ray;
  }
  // Sphere: end at its near surface (the cap the point sees), so nothing inside the light occludes it.
  const float b = glm::dot(ray.dir, centre_);
  const float t = b - std::sqrt(std::max(0.0f, b * b - sphere_c_));
  ray.tfar = t * detail::kShadowTfarScale;
  return ray;
}

double LightView::cone_solid_angle() const {
  const bool cone = shape_ == SampledLight::Shape::kSphere || shape_ == SampledLight::Shape::kSunDisk;
  return cone ? 2.0 * std::numbers::pi * static_cast<double>(one_minus_cos_max_) : 0.0;
}

}  // namespace dhr::server
