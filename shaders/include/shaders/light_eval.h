// Light evaluation shared by GLSL and C++ (glTF KHR_lights_punctual, physically based falloff; EXT_lights_area rect
// and disk lights are evaluated as a one-sided, cosine-weighted point light at their centre: unshadowed shading and
// the hard-shadow ray both use the centre).
// The server's tracers and the client's shading pass include this one file, so the CPU and the GPU decide
// "this light can contribute at this surface point" with the same arithmetic.
//
// Written in the common subset of GLSL 4.5 and C++20 with GLM: float literals carry an `f` suffix (valid
// in both), no swizzles (vec3(v4) instead of v4.xyz), parameters through the LE_IN/LE_OUT macros.
// GLSL: `#include "shaders/light_eval.h"` (GL_GOOGLE_include_directive; dhr_add_shader_library passes the
// include directory). C++: include "scene/lighting.hpp", which includes this header (namespace
// dhr::light_eval) through the dhr_shader_headers target.
//
// All positions (surface points, PackedLight positions) must be in the same frame; callers pick one
// close to the data (scene-centre- or camera-relative) so that large world coordinates keep precision.
#ifndef DHR_LIGHT_EVAL_H
#define DHR_LIGHT_EVAL_H

#ifdef __cplusplus
#include <glm/geometric.hpp>
#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#define LE_IN(T) const T&
#define LE_OUT(T) T&
#define LE_FN inline
#define LE_CONST inline constexpr
namespace dhr::light_eval {
using glm::clamp;
using glm::dot;
using glm::length;
using glm::max;
using glm::vec3;
using glm::vec4;
#else
#define LE_IN(T) in T
#define LE_OUT(T) out T
#define LE_FN
#define LE_CONST const
#endif

// One light, 64 bytes, the same layout in C++ and in a std140/std430 GLSL buffer.
struct PackedLight {
  vec4 position_type;    // xyz: position (point, spot; rect, disk: centre) in the caller's frame; w: kLightType*
  vec4 direction_range;  // xyz: unit direction the light travels (spot, directional; rect, disk: emission normal);
                         // w: range, 0 = infinite
  vec4 color_intensity;  // rgb: linear colour; w: intensity (candela for point/spot, lux for directional; rect,
                         // disk: candela along the emission normal = nits x area)
  vec4 spot;             // x: cos(outer cone); y: angle scale; z: angle offset (glTF); w: unused
};

LE_CONST float kLightTypePoint = 0.0f;
LE_CONST float kLightTypeSpot = 1.0f;
LE_CONST float kLightTypeDirectional = 2.0f;
LE_CONST float kLightTypeRect = 3.0f;
LE_CONST float kLightTypeDisk = 4.0f;

// Results of light_test: why a light cannot contribute, or that it can.
LE_CONST int kLightContributes = 0;
LE_CONST int kLightOutOfRange = 1;   // beyond the range, outside the spot's outer cone, or at the light
LE_CONST int kLightBackfacing = 2;   // N.L <= 0

// Distance reported for directional lights (finite so it survives GLSL and fast-math arithmetic).
LE_CONST float kLightInfiniteDistance = 3.0e38f;

LE_FN bool light_is_directional(LE_IN(PackedLight) light) {
  return light.position_type.w > 1.5f && light.position_type.w < 2.5f;
}
LE_FN bool light_is_spot(LE_IN(PackedLight) light) {
  return light.position_type.w > 0.5f && light.position_type.w < 1.5f;
}
// Rect or disk: one-sided, emitting along direction_range.xyz with Lambert's cosine.
LE_FN bool light_is_area(LE_IN(PackedLight) light) { return light.position_type.w > 2.5f; }

// Unit direction from p toward the light, and the distance to it.
LE_FN void light_direction(LE_IN(PackedLight) light, vec3 p, LE_OUT(vec3) out_l, LE_OUT(float) out_distance) {
  if (light_is_directional(light)) {
    out_l = -vec3(light.direction_range);
    out_distance = kLightInfiniteDistance;
    return;
  }
  const vec3 d = vec3(light.position_type) - p;
  const float dist = length(d);
  out_distance = dist;
  out_l = dist > 0.0f ? d / dist : vec3(0.0f, 1.0f, 0.0f);
}

// Whether the light can contribute at surface point p with (unit) normal n, ignoring occluders. Range, cone and
// an area light's back side come first, so a pair that fails both is reported as kLightOutOfRange. Also returns L
// and distance. Strict comparisons: at exactly the range, the outer cone or the emitter's plane the falloff is zero.
LE_FN int light_test(LE_IN(PackedLight) light, vec3 p, vec3 n, LE_OUT(vec3) out_l, LE_OUT(float) out_distance) {
  light_direction(light, p, out_l, out_distance);
  if (!light_is_directional(light)) {
    if (!(out_distance > 0.0f)) return kLightOutOfRange;
    const float range = light.direction_range.w;
    if (range > 0.0f && !(out_distance < range)) return kLightOutOfRange;
    if (light_is_spot(light) && !(dot(-out_l, vec3(light.direction_range)) > light.spot.x)) return kLightOutOfRange;
    if (light_is_area(light) && !(dot(-out_l, vec3(light.direction_range)) > 0.0f)) return kLightOutOfRange;
  }
  if (!(dot(n, out_l) > 0.0f)) return kLightBackfacing;
  return kLightContributes;
}

// Distance and angular attenuation (glTF): 1/d^2 with the recommended smooth range window
// saturate(1 - (d/range)^4)^2, times the spot's saturate(cd * scale + offset)^2, or an area light's
// max(0, cos) between its emission normal and the direction to the point (Lambert). Directional: 1.
LE_FN float light_attenuation(LE_IN(PackedLight) light, vec3 l, float distance) {
  if (light_is_directional(light)) return 1.0f;
  float attenuation = 1.0f / max(distance * distance, 1.0e-8f);
  const float range = light.direction_range.w;
  if (range > 0.0f) {
    const float x = distance / range;
    const float window = clamp(1.0f - x * x * x * x, 0.0f, 1.0f);
    attenuation *= window * window;
  }
  if (light_is_spot(light)) {
    const float cd = dot(-l, vec3(light.direction_range));
    const float angular = clamp(cd * light.spot.y + light.spot.z, 0.0f, 1.0f);
    attenuation *= angular * angular;
  }
  if (light_is_area(light)) attenuation *= max(dot(-l, vec3(light.direction_range)), 0.0f);
  return attenuation;
}

// Irradiance E (linear RGB) arriving at the point from the light, before the N.L factor.
LE_FN vec3 light_irradiance(LE_IN(PackedLight) light, vec3 l, float distance) {
  return vec3(light.color_intensity) * (light.color_intensity.w * light_attenuation(light, l, distance));
}

// saturate(N.L): the Lambert cosine factor of the shading equation.
LE_FN float light_cosine(vec3 n, vec3 l) { return clamp(dot(n, l), 0.0f, 1.0f); }

#ifdef __cplusplus
}  // namespace dhr::light_eval
#endif

#undef LE_IN
#undef LE_OUT
#undef LE_FN
#undef LE_CONST
#endif  // DHR_LIGHT_EVAL_H
