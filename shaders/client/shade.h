// The client's shading equation (GLSL; included by shading.comp and client/forward_body.h):
//   radiance = albedo / pi * sum_i k_i * saturate(N.L_i) * E_i
// with k_i bit i of the light mask and the light math of light_eval.h (the server's notion of "contributes").
// The lights are client/light_buffer.h's: define its DHR_LIGHT_BUFFER_SET and DHR_LIGHT_BUFFER_BINDING first.
// p: the surface point relative to the eye (world axes); n: unit normal.
#ifndef DHR_SHADE_H
#define DHR_SHADE_H

#include "shaders/light_eval.h"
#include "client/light_buffer.h"

vec3 shade_radiance(vec3 p, vec3 n, vec3 albedo, uint mask, uint light_count) {
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < light_count; ++i) {
    if (((mask >> i) & 1u) == 0u) continue;  // shadowed: skipped when no invocation needs the light
    vec3 l;
    float dist;
    if (light_test(lights[i], p, n, l, dist) != kLightContributes) continue;
    sum += light_irradiance(lights[i], l, dist) * light_cosine(n, l);
  }
  return albedo * 0.31830988618379067 * sum;
}

#endif  // DHR_SHADE_H
