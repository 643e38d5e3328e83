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

// No slot table row: field f is light f.
const uint kNoSlotRow = 0xFFFFFFFFu;

#ifdef DHR_LIGHT_SLOTS_BINDING
// Light slots (more than 32 lights; scene/light_slots.hpp): the table the shader defines DHR_LIGHT_SLOTS_BINDING for
// (in DHR_LIGHT_BUFFER_SET), in LightSlots::gpu_words' format.
layout(set = DHR_LIGHT_BUFFER_SET, binding = DHR_LIGHT_SLOTS_BINDING, std430) readonly buffer LightSlotTable {
  uint light_slot_table[];
};

// Where the lights of the cell holding p start in light_slot_table (p and origin_mm relative to the eye, world axes;
// binned in float: a point within the margin of a cell boundary may fall in either cell, and a light reaching it
// is registered in both, in the same slot).
uint light_slot_row(vec3 p, vec3 origin_mm) {
  const float cell = uintBitsToFloat(light_slot_table[3]);
  const uvec3 cells = uvec3(light_slot_table[4], light_slot_table[5], light_slot_table[6]);
  const vec3 c = floor((p * 1000.0 - origin_mm) / cell);
  uint index = cells.x * cells.y * cells.z;  // the row outside the grid
  if (all(greaterThanEqual(c, vec3(0.0))) && all(lessThan(c, vec3(cells))))
    index = (uint(c.z) * cells.y + uint(c.y)) * cells.x + uint(c.x);
  return kVisSlotHeaderWords + index * light_slot_table[7];
}

// The light of field f: the one the row's cell gives slot f (kVisNoSlotLight: none), or f without a row.
uint field_light(uint f, uint row) { return row == kNoSlotRow ? f : light_slot_table[row + f]; }
#else
uint field_light(uint f, uint row) { return f; }
#endif

// The refined share of soft field `rank` in `refined` (kClientWarpSoftRefine's packed bytes), or -1: none.
float shade_refined_share(uint refined, uint rank) {
  if (rank >= kClientSoftRefineFields) return -1.0;
  const uint byte = (refined >> (8u * rank)) & 0xFFu;
  return byte == kClientSoftRefineNone ? -1.0 : float(byte) / float(kClientSoftRefineScale);
}

// The sum over the mask's fields, field f shading field_light(f, row); a soft field with a refined share in
// `refined` (kClientSoftRefineNoneAll: none) shades with it instead of its level.
vec3 shade_fields(vec3 p, vec3 n, vec3 albedo, uint mask, uint fields, uint soft_fields, uint row, uint refined) {
  vec3 sum = vec3(0.0);
  uint offset = 0u, rank = 0u;
  for (uint f = 0u; f < fields; ++f) {
    const uint bits = field_bits(soft_fields, f);
    const uint at = offset;
    offset += bits;
    const float share = bits > 1u ? shade_refined_share(refined, rank++) : -1.0;
    // Shadowed: skipped when no invocation needs it.
    if (((mask >> at) & ((1u << bits) - 1u)) == 0u && !(share > 0.0)) continue;
    const uint li = field_light(f, row);
    if (li == kVisNoSlotLight) continue;
    vec3 term;
    if (!shade_light_term(li, p, n, term)) continue;
    // A hard light adds its term as it is (k = 1), so masks without soft fields shade exactly as before.
    sum += bits == 1u ? term : (share >= 0.0 ? share : field_visibility(mask, at, bits)) * term;
  }
  return albedo * 0.31830988618379067 * sum;
}

vec3 shade_radiance(vec3 p, vec3 n, vec3 albedo, uint mask, uint light_count, uint soft_lights, uint refined) {
  return shade_fields(p, n, albedo, mask, light_count, soft_lights, kNoSlotRow, refined);
}

#ifdef DHR_LIGHT_SLOTS_BINDING
// shade_radiance with the mask's fields as light slots: field f adds the light slot f holds where p is (none: 0).
vec3 shade_radiance_slots(vec3 p, vec3 n, vec3 albedo, uint mask, uint fields, uint soft_fields, vec3 origin_mm) {
  return shade_fields(p, n, albedo, mask, fields, soft_fields, light_slot_row(p, origin_mm), kClientSoftRefineNoneAll);
}
#endif

#endif  // DHR_SHADE_H
