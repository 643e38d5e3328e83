// Samples over a light's extent as one ray origin sees it: server/trace/src/soft/light_sampler.cpp in GLSL, for the
// ray-tracing backend's soft fields. The sample points are the same integers (uint arithmetic wraps as uint32_t
// does): hash_u32, the Owen scramble, Sobol's second dimension and the 24-bit fixed point, so both backends take
// identical points in [0, 1)^2. Their mapping onto the light is float here (the CPU sets each view up in double and
// maps the disk in double): ray directions agree to a few ULPs (the measured bound: docs/server.md).
// Needs shaders/shader_interface.h (VisSoftLight, kVisSoft*, kVisShadowTfarScale).
#ifndef DHR_LIGHT_SAMPLER_GLSL
#define DHR_LIGHT_SAMPLER_GLSL

const float kSoftFarAway = 3.0e38;  // the sun's rays: "infinite" tmax, as the hard rays'

// Wellons' "lowbias32" (hash_u32).
uint soft_hash(uint x) {
  x ^= x >> 16u;
  x *= 0x7feb352du;
  x ^= x >> 15u;
  x *= 0x846ca68bu;
  x ^= x >> 16u;
  return x;
}

// Burley 2020's hash-based Owen scramble of a 32-bit fixed-point coordinate (owen_scramble).
uint soft_owen_scramble(uint x, uint seed) {
  x = bitfieldReverse(x);
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return bitfieldReverse(x);
}

// Sobol's second dimension (sobol_dim1): direction v_k = v_{k-1} ^ (v_{k-1} >> 1).
uint soft_sobol_dim1(uint index) {
  uint x = 0u, v = 0x80000000u;
  for (; index != 0u; index >>= 1u, v ^= v >> 1u)
    if ((index & 1u) != 0u) x ^= v;
  return x;
}

float soft_to_unit(uint x) { return float(x >> 8u) * 5.9604644775390625e-8; }  // 2^-24: exact

// Point `index` of the (0,2)-sequence scrambled by `seed` (sample_2d).
vec2 soft_sample_2d(uint index, uint seed) {
  return vec2(soft_to_unit(soft_owen_scramble(bitfieldReverse(index), soft_hash(seed))),
              soft_to_unit(soft_owen_scramble(soft_sobol_dim1(index), soft_hash(seed ^ 0x68bc21ebu))));
}

// What one ray origin sees of one light with an extent (LightView).
struct SoftView {
  uint shape;
  vec3 axis, b1, b2;        // cone frame (sphere, sun)
  float one_minus_cos_max;  // cone: 1 - cos(half-angle)
  vec3 centre;              // sphere, rect, disk: relative to the origin
  float sphere_c;           // sphere: |centre|^2 - radius^2
  vec3 half_u, half_v;      // rect, disk
};

const int kSoftViewNothing = 0;  // behind (or in the plane of) a one-sided emitter: nothing arrives, no ray
const int kSoftViewHardRay = 1;  // punctual, or inside a sphere light: the hard tracer's ray decides
const int kSoftViewSample = 2;   // samples over the extent

// Duff et al. 2017's orthonormal frame around unit n; copysign(1, n.z) as the CPU (-0 counts as negative).
void soft_basis(vec3 n, out vec3 b1, out vec3 b2) {
  const float sign = (floatBitsToUint(n.z) & 0x80000000u) != 0u ? -1.0 : 1.0;
  const float a = -1.0 / (sign + n.z);
  const float b = n.x * n.y * a;
  b1 = vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  b2 = vec3(b, sign + n.y * n.y * a, -n.y);
}

int soft_view_create(VisSoftLight light, vec3 origin, out SoftView v) {
  v.shape = light.shape;
  v.centre = vec3(light.centre_x, light.centre_y, light.centre_z) - origin;
  v.half_u = vec3(light.half_u_x, light.half_u_y, light.half_u_z);
  v.half_v = vec3(light.half_v_x, light.half_v_y, light.half_v_z);
  v.sphere_c = 0.0;
  const vec3 direction = vec3(light.direction_x, light.direction_y, light.direction_z);
  if (light.shape == kVisSoftPunctual) return kSoftViewHardRay;
  if (light.shape == kVisSoftRect || light.shape == kVisSoftDisk)
    return dot(-v.centre, direction) > 0.0 ? kSoftViewSample : kSoftViewNothing;
  if (light.shape == kVisSoftSphere) {
    const float d = length(v.centre);
    if (!(d > light.radius)) return kSoftViewHardRay;  // inside the sphere: no cap to sample
    v.axis = v.centre / d;
    const float sin_max = light.radius / d;
    const float sin2 = sin_max * sin_max;
    v.one_minus_cos_max = sin2 / (1.0 + sqrt(1.0 - sin2));  // 1 - cos without cancellation for small caps
    v.sphere_c = dot(v.centre, v.centre) - light.radius * light.radius;
  } else {  // sun disk
    v.axis = -direction;
    v.one_minus_cos_max = light.sun_one_minus_cos;
  }
  soft_basis(v.axis, v.b1, v.b2);
  return kSoftViewSample;
}

// Shirley-Chiu concentric map of [0,1)^2 onto the unit disk.
vec2 soft_concentric_disk(vec2 u) {
  const float a = 2.0 * u.x - 1.0, b = 2.0 * u.y - 1.0;
  if (a == 0.0 && b == 0.0) return vec2(0.0);
  const float quarter_pi = 0.78539816339744831;
  if (abs(a) > abs(b)) {
    const float phi = quarter_pi * (b / a);
    return a * vec2(cos(phi), sin(phi));
  }
  const float phi = 2.0 * quarter_pi - quarter_pi * (a / b);
  return b * vec2(cos(phi), sin(phi));
}

// The ray of sample point u (LightView::sample): its unit direction and tmax.
void soft_view_sample(SoftView v, vec2 u, out vec3 dir, out float tmax) {
  if (v.shape == kVisSoftRect || v.shape == kVisSoftDisk) {
    const vec2 q = v.shape == kVisSoftRect ? 2.0 * u - 1.0 : soft_concentric_disk(u);
    const vec3 d = v.centre + q.x * v.half_u + q.y * v.half_v;
    const float dist = length(d);
    dir = d / dist;
    tmax = dist * kVisShadowTfarScale;  // the emitter's own surface is no occluder
    return;
  }
  // Uniform in the cone's solid angle: 1 - cos(theta) uniform in [0, 1 - cos_max), phi uniform.
  const float om = u.x * v.one_minus_cos_max;
  const float sin_theta = sqrt(max(0.0, om * (2.0 - om)));
  const float phi = 6.283185307179586 * u.y;
  dir = normalize((1.0 - om) * v.axis + sin_theta * (cos(phi) * v.b1 + sin(phi) * v.b2));
  if (v.shape == kVisSoftSunDisk) {
    tmax = kSoftFarAway;
    return;
  }
  // Sphere: end at its near surface, so nothing inside the light occludes it.
  const float b = dot(dir, v.centre);
  tmax = (b - sqrt(max(0.0, b * b - v.sphere_c))) * kVisShadowTfarScale;
}

#endif  // DHR_LIGHT_SAMPLER_GLSL
