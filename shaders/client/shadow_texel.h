// The client's shadow-map texels (GLSL; included by client/pcss.h and client/shadow_lookup.h): what a texel of a
// light's tile stores, and where a point falls in a sun's orthographic tile (a cube's faces: client/cube_face.h).
#ifndef DHR_SHADOW_TEXEL_H
#define DHR_SHADOW_TEXEL_H

#include "shaders/shader_interface.h"
#include "client/cube_face.h"
#include "client/float3.h"

// The occluder distance the atlas texel t (clamped to the face) of light sl's tile, cube face `face` stores:
// along the face's axis (cube), from the map's near plane (sun); 3e38 where nothing is.
float shadow_occluder(sampler2D atlas, ClientWarpParams params, ClientShadowLight sl, uint face, ivec2 t) {
  const uint size = params.shadow_size;
  const ivec2 c = clamp(t, ivec2(0), ivec2(int(size) - 1));
  const float stored = texelFetch(atlas, ivec2(face * size + uint(c.x), sl.tile_row * size + uint(c.y)), 0).r;
  if ((sl.flags & kClientShadowSun) != 0u) return stored > 0.0 ? (1.0 - stored) * sl.depth_range : 3.0e38;
  return stored > 0.0 ? params.shadow_near / stored : 3.0e38;
}

// Whether that texel is at or beyond `threshold`.
bool shadow_texel_lit(sampler2D atlas, ClientWarpParams params, ClientShadowLight sl, uint face, ivec2 t,
                      float threshold) {
  return shadow_occluder(atlas, params, sl, face, t) >= threshold;
}

// Where a point (relative to the light's map origin, normal-offset) falls in a sun's orthographic tile.
CubeLookup sun_lookup(ClientShadowLight sl, vec3 v, uint size) {
  const vec3 right = v3(sl.right);
  const vec3 up = v3(sl.up);
  CubeLookup c;
  c.face = 0u;
  c.distance = dot(v, cross(up, right));
  const float s = float(size);
  c.position = vec2((dot(v, right) / sl.half_extent + 1.0) * 0.5 * s, (1.0 - dot(v, up) / sl.half_extent) * 0.5 * s);
  c.texel = clamp(ivec2(floor(c.position)), ivec2(0), ivec2(int(size) - 1));
  return c;
}

#endif  // DHR_SHADOW_TEXEL_H
