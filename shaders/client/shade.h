// The client's shading equation (GLSL; included by shading.comp and client/forward_body.h):
//   radiance = albedo / pi * sum_i k_i * saturate(N.L_i) * E_i
// with k_i light i's field of the light mask (client/visibility_field.h: a hard light's bit, a soft light's
// level / (levels - 1)) and the light math of light_eval.h (the server's notion of "contributes").
// The lights are client/light_buffer.h's: define its DHR_LIGHT_BUFFER_SET and DHR_LIGHT_BUFFER_BINDING first.
// p: the surface point relative to the eye (world axes); n: unit normal; soft_lights: bit i = light i is soft.
#ifndef DHR_SHADE_H
#define DHR_SHADE_H

#include "shaders/light_eval.h"
#include "client/light_buffer.h"
#include "client/visibility_field.h"

// Light i's unshadowed term saturate(N.L) E at p, or false where it cannot contribute.
bool shade_light_term(uint i, vec3 p, vec3 n, out vec3 term) {
  vec3 l;
  float dist;
  term = vec3(0.0);
  if (light_test(lights[i], p, n, l, dist) != kLightContributes) return false;
  term = light_irradiance(lights[i], l, dist) * light_cosine(n, l);
  return true;
}

vec3 shade_radiance(vec3 p, vec3 n, vec3 albedo, uint mask, uint light_count, uint soft_lights) {
  vec3 sum = vec3(0.0);
  uint offset = 0u;
  for (uint i = 0u; i < light_count; ++i) {
    const uint bits = field_bits(soft_lights, i);
    const uint at = offset;
    offset += bits;
    if (((mask >> at) & ((1u << bits) - 1u)) == 0u) continue;  // shadowed: skipped when no invocation needs it
    vec3 term;
    if (!shade_light_term(i, p, n, term)) continue;
    // A hard light adds its term as it is (k = 1), so masks without soft fields shade exactly as before.
    sum += bits == 1u ? term : field_visibility(mask, at, bits) * term;
  }
  return albedo * 0.31830988618379067 * sum;
}

#endif  // DHR_SHADE_H
