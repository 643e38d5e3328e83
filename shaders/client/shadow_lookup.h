// The client's shadow-map lookup (GLSL; included by warp.comp and client/forward_body.h). The CPU reference is
// render/shadow_maps.cpp's shadow_mask_reference. The warp's parameters (ClientWarpParams: light_count and the
// shadow_* fields) and the shadow-map atlas come as arguments; the two per-light buffers the lookup loops over
// are declared by headers (GLSL cannot pass them), at bindings the shader defines before including this:
//   DHR_LIGHT_BUFFER_SET, DHR_LIGHT_BUFFER_BINDING                PackedLight[] (client/light_buffer.h)
//   DHR_SHADOW_LIGHT_BUFFER_SET, DHR_SHADOW_LIGHT_BUFFER_BINDING  ClientShadowLight[] (below)
#ifndef DHR_SHADOW_LOOKUP_H
#define DHR_SHADOW_LOOKUP_H

#if !defined(DHR_SHADOW_LIGHT_BUFFER_SET) || !defined(DHR_SHADOW_LIGHT_BUFFER_BINDING)
#error "define DHR_SHADOW_LIGHT_BUFFER_SET and DHR_SHADOW_LIGHT_BUFFER_BINDING before including client/shadow_lookup.h"
#endif

#include "shaders/shader_interface.h"
#include "shaders/light_eval.h"
#include "client/cube_face.h"
#include "client/float3.h"
#include "client/light_buffer.h"
#include "client/visibility_field.h"

layout(set = DHR_SHADOW_LIGHT_BUFFER_SET, binding = DHR_SHADOW_LIGHT_BUFFER_BINDING, std430)
readonly buffer ShadowLights {
  ClientShadowLight shadow_lights[];
};

// The shadow maps at surface point p (display-eye-relative, world axes) with unit normal n, per light: `mask`
// 0 where the light cannot contribute (light_test) or the texel under the lookup holds a nearer surface than the
// point (less the bias), else 1; `confident` unless a texel is coarser than a display pixel (`pixel_world`
// metres at p) and the 2x2 texels around the lookup decide differently (a shadow edge within a texel). A band
// of doubt around the bias (a shadow cast from within a few biases may be acne) was measured and dropped: on
// the living room the server's bits were wrong there more often than the maps' (docs/evaluation.md).
struct ShadowLookup {
  uint mask;
  uint confident;
};

#include "client/pcss.h"

// Light i's share at p (0 or 1 for a hard light, PCSS's fraction for a soft one) and whether the maps are
// confident of it (see ShadowLookup), for a light that can contribute there (light_test: l = direction to it).
struct ShadowLight {
  float fraction;
  bool confident;
};

ShadowLight shadow_light_lookup(ClientWarpParams params, sampler2D atlas, ClientShadowLight sl, vec3 p, vec3 n,
                                vec3 l, float pixel_world) {
  ShadowLight r;
  if (sl.tile_row == kClientNoShadowMap) {  // no map (a directional light without an angle): lit, never confident
    r.fraction = 1.0;
    r.confident = false;
    return r;
  }
  const float size = float(params.shadow_size);
  const vec3 v0 = p - v3(sl.position);
  const bool sun = (sl.flags & kClientShadowSun) != 0u;
  // Normal offset: a few texels (at this distance) along the normal, against acne on slopes.
  const float texel = sun ? 2.0 * sl.half_extent / size : 2.0 * cube_face_distance(v0) / size;
  const vec3 v = v0 + (params.shadow_normal_offset * texel) * n;
  const CubeLookup c = sun ? sun_lookup(sl, v, params.shadow_size) : cube_lookup(v, params.shadow_size);
  // Slope-scaled: a texel spans more depth the more grazing the light (tan of the angle, at most 10).
  const float cos_nl = dot(n, l);
  const float tan_nl = min(sqrt(max(1.0 - cos_nl * cos_nl, 0.0)) / cos_nl, 10.0);
  if (sl.mask_bits != 1u) {
    // Soft: PCSS; confident where every filter tap agrees (fully lit or fully shadowed).
    const float base_bias = params.shadow_bias_rel * c.distance + params.shadow_bias_abs;
    // Texels per unit of the similar-triangles term: cube R s / d (times (d - z) / z), sun tan / texel (times
    // d - z).
    const float scale = sun ? sl.radius / texel : sl.radius / c.distance * (0.5 * size);
    r.fraction = pcss_fraction(params, atlas, sl, c.face, c.position, c.distance, scale, base_bias, texel * tan_nl);
    r.confident = r.fraction == 0.0 || r.fraction == 1.0;
    return r;
  }
  const float bias =
      params.shadow_bias_rel * c.distance + params.shadow_bias_abs + params.shadow_bias_slope * texel * tan_nl;
  const float threshold = c.distance - bias;
  const bool lit = shadow_texel_lit(atlas, params, sl, c.face, c.texel, threshold);
  r.fraction = lit ? 1.0 : 0.0;
  // Confidence: the 2x2 footprint around the lookup.
  bool alike = true;
  if (texel > pixel_world) {
    const ivec2 t0 = ivec2(floor(c.position - 0.5));
    for (int k = 0; k < 4; ++k) {
      alike = alike && shadow_texel_lit(atlas, params, sl, c.face, t0 + ivec2(k & 1, k >> 1), threshold) == lit;
    }
  }
  r.confident = alike;
  return r;
}

// The mask of the lights whose field meets `wanted`, each in its field (ClientShadowLight::mask_offset, mask_bits):
// a hard light's bit, a soft light's level (Gray-coded); `confident` has all bits of a light's field set where the
// maps are confident of it (or the light cannot contribute). The other lights' fields are 0 and not looked up (the
// caller takes only `wanted` bits from the maps).
ShadowLookup shadow_lookup_fields(ClientWarpParams params, sampler2D atlas, vec3 p, vec3 n, float pixel_world,
                                  uint wanted) {
  ShadowLookup r;
  r.mask = 0u;
  r.confident = 0u;
  for (uint i = 0u; i < params.light_count; ++i) {
    const ClientShadowLight sl = shadow_lights[i];
    const uint field = ((1u << sl.mask_bits) - 1u) << sl.mask_offset;
    if ((field & wanted) == 0u) continue;
    vec3 l;
    float dist;
    if (light_test(lights[i], p, n, l, dist) != kLightContributes) {
      r.confident |= field;
      continue;
    }
    const ShadowLight s = shadow_light_lookup(params, atlas, sl, p, n, l, pixel_world);
    r.mask |= field_from_fraction(s.fraction, sl.mask_offset, sl.mask_bits);
    if (s.confident) r.confident |= field;
  }
  return r;
}

// Every light's field (shadow_lookup_fields of all bits).
ShadowLookup shadow_lookup(ClientWarpParams params, sampler2D atlas, vec3 p, vec3 n, float pixel_world) {
  return shadow_lookup_fields(params, atlas, p, n, pixel_world, 0xFFFFFFFFu);
}

#endif  // DHR_SHADOW_LOOKUP_H
