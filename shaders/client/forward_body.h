// The forward pass's fragment shader (render/forward_pass.hpp), included by forward.frag (colour only),
// forward_status.frag (+ the status attachment) and forward_status_mask.frag (+ the mask attachment): each
// pipeline declares exactly the outputs it has attachments for. The includer defines DHR_FORWARD_STATUS and
// DHR_FORWARD_MASK (0 or 1) before including this.
#include "shaders/shader_interface.h"
#include "shaders/display_encode.h"
#include "client/float3.h"

// Forward: the G-buffer pass's material evaluation (gbuffer.frag: alpha mask, normal flipped on back faces),
// then this fragment's light mask and the shading equation, in the raster pass: no G-buffer round trip. The mask
// is, by mode (ClientForwardShading::mode, dynamically uniform):
//   kClientForwardLambert     all lights (no shadows: the cost of not having shadows); with light slots, each
//                             field's light where the fragment is (clustered by the slots' grid)
//   kClientForwardShadowMaps  the client's shadow maps (what a headset would do without DHR; PCSS for soft
//                             lights, whose fraction is k_i unquantized)
//   kClientForwardPaperWarp   the paper's warp of this eye's newest visibility (the DHR client)
//   kClientForwardServerEdges this eye's newest visibility, 2x2 bilinear samples: bits they agree on from the
//                             server, the others and pixels without a sample from the shadow maps, which are
//                             looked up only there (WarpSettings::server_edges); with kClientWarpDepthTest the
//                             samples off the pixel's tangent plane in the traced depth are not used; with
//                             kClientWarpSoftRefine soft fields shade with their refined shares (warp.comp's)
// The surface point comes from gl_FragCoord (pixel centre, reversed-Z depth) with the same formula the compute
// passes apply to the depth image: the warp decisions equal the compute warp's and its CPU reference.
layout(set = 0, binding = kClientGBufferBindingBaseColor) uniform sampler2D base_color_texture;
layout(set = 1, binding = kClientForwardBindingParams, std430) restrict readonly buffer Params { ClientWarpParams pc; };
layout(set = 1, binding = kClientForwardBindingVisibility0, std430) readonly buffer Visibility0 { uint vis0[]; };
uint warp_share_load(uint, uint word) { return vis0[word]; }  // bilinear_warp.h's band shares (source 0)
layout(set = 1, binding = kClientForwardBindingRowValid0, std430) readonly buffer RowValid0 { uint rows0[]; };
layout(set = 1, binding = kClientForwardBindingShadowMap) uniform sampler2D shadow_atlas;
layout(set = 1, binding = kClientForwardBindingTracedDepth0) uniform sampler2D traced_depth0;
layout(set = 1, binding = kClientForwardBindingShading, std430) restrict readonly buffer Shading {
  ClientForwardShading shading;
};
layout(push_constant, std430) uniform Push { ClientGBufferPush mat; };

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec2 in_uv;

layout(location = 0) out vec4 out_colour;
#if DHR_FORWARD_STATUS
layout(location = 1) out uint out_status;
#endif
#if DHR_FORWARD_MASK
layout(location = 2) out uint out_mask;
#endif

// The lights and their shadow-map tiles are declared by the helpers (client/light_buffer.h, shadow_lookup.h).
#define DHR_LIGHT_BUFFER_SET 1
#define DHR_LIGHT_BUFFER_BINDING kClientForwardBindingLights
#define DHR_SHADOW_LIGHT_BUFFER_SET 1
#define DHR_SHADOW_LIGHT_BUFFER_BINDING kClientForwardBindingShadowLights
#include "client/shadow_lookup.h"
#include "client/paper_warp.h"
#include "client/bilinear_warp.h"
#define DHR_MOTION_BUFFER_SET 1
#define DHR_MOTION_BUFFER_BINDING kClientForwardBindingMoved
#include "client/motion_rule.h"
#define DHR_LIGHT_SLOTS_BINDING kClientForwardBindingLightSlots
#include "client/shade.h"

// kClientForwardShadowMaps: the shadow maps' mask (as shadow_lookup) and the shading with each light's share
// itself as k_i: a soft light's PCSS fraction unquantized (the mask holds its level), a hard light's bit.
vec3 shade_local(vec3 p, vec3 n, vec3 albedo, float pixel_world, out uint mask) {
  vec3 sum = vec3(0.0);
  mask = 0u;
  for (uint i = 0u; i < pc.light_count; ++i) {
    const ClientShadowLight sl = shadow_lights[i];
    vec3 l;
    float dist;
    if (light_test(lights[i], p, n, l, dist) != kLightContributes) continue;
    const float k = shadow_light_lookup(pc, shadow_atlas, sl, p, n, l, pixel_world).fraction;
    mask |= field_from_fraction(k, sl.mask_offset, sl.mask_bits);
    if (!(k > 0.0)) continue;
    vec3 term;
    if (!shade_light_term(i, p, n, term)) continue;
    sum += sl.mask_bits == 1u ? term : k * term;
  }
  return albedo * 0.31830988618379067 * sum;
}

void main() {
  const vec4 factor = vec4(mat.base_color_r, mat.base_color_g, mat.base_color_b, mat.base_color_a);
  const vec4 base = texture(base_color_texture, in_uv) * factor;
  if ((mat.flags & kClientMaterialAlphaMask) != 0u && base.a < mat.alpha_cutoff) discard;
  const float len2 = dot(in_normal, in_normal);
  vec3 n = len2 > 1e-20 ? in_normal * inversesqrt(len2) : vec3(0.0, 1.0, 0.0);
  if (!gl_FrontFacing) n = -n;
  const vec3 albedo = clamp(base.rgb, 0.0, 1.0);

  const float d = gl_FragCoord.z;
  const vec2 centre = gl_FragCoord.xy;
  const vec3 p = (pc.near_plane / d) * (v3(pc.world_ray0) + centre.x * v3(pc.world_ray_dx) + centre.y * v3(pc.world_ray_dy));
  uint mask = fields_all_lit(shading.soft_lights, shading.light_count);
  uint refined = kClientSoftRefineNoneAll;  // kClientWarpSoftRefine: the soft fields' refined shares
  uint status = kClientStatusKnown;
  bool shaded = false;
  vec3 radiance = vec3(0.0);
  if (shading.mode == kClientForwardPaperWarp) {
    const PaperWarpLookup at = paper_warp_lookup(pc, centre, d);
    const uint row_word = paper_warp_reads_rows(pc) ? rows0[at.row >> 5] : 0u;
    vec2 motion;
    status = paper_warp(pc, centre, d, at, row_word, vis0[at.mask_bit >> 5], mask, motion);
  } else if (shading.mode == kClientForwardServerEdges) {
    // warp.comp's decisions with bilinear, shadow_edges and shadow_fill alone, in its order.
    const ClientWarpSource src = pc.source[0];
    const PaperWarpLookup at = paper_warp_lookup(pc, centre, d);
    const vec2 q = at.pixel;
    const bool inside = q.x >= 0.0 && q.y >= 0.0 && q.x < float(src.old_width) && q.y < float(src.old_height);
    status = (src.flags & kClientSourceHasVisibility) == 0u ? kClientStatusNoData
           : !(at.depth_old > pc.min_depth) ? kClientStatusBehind
           : !inside ? kClientStatusOutside
           : kClientStatusKnown;
    uint value = 0u;
    uint undecided = 0u;  // known: the bits the samples disagree on
    if (status == kClientStatusKnown) {
      const WarpSamples samples = warp_samples(q, true);
      // The depth test (warp.comp's look_up): a sample whose traced surface is off this pixel's tangent plane
      // saw something else (an occluder since moved out of the way); not used.
      const bool depth_test = (pc.flags & kClientWarpDepthTest) != 0u && (src.flags & kClientSourceHasDepth) != 0u;
      const bool same_ray = samples.centred && (src.flags & kClientSourceSameEye) != 0u;
      vec3 p_old = vec3(0.0), n_old = vec3(0.0);
      float tolerance = 0.0;
      if (depth_test) {  // dynamically uniform: without the test nothing of it is computed
        p_old = (pc.near_plane / d) * (v3(src.ray0) + centre.x * v3(src.ray_dx) + centre.y * v3(src.ray_dy)) +
                v3(src.trans);
        n_old = vec3(src.rot[0] * n.x + src.rot[1] * n.y + src.rot[2] * n.z,
                     src.rot[3] * n.x + src.rot[4] * n.y + src.rot[5] * n.z,
                     src.rot[6] * n.x + src.rot[7] * n.y + src.rot[8] * n.z);
        tolerance = pc.plane_tolerance_rel * at.depth_old + pc.plane_tolerance_abs;
      }
      uint masks[4];
      uint used = 0u, rows = 0u, marks = 0u, arrived = 0u;
      for (int k = 0; k < 4; ++k) {
        masks[k] = 0u;
        const ivec2 c = warp_sample_pixel(samples, k);
        if (!warp_sample_in_buffer(src, c)) continue;
        const uint row_word = paper_warp_reads_rows(pc) ? rows0[uint(c.y) >> 5] : 0u;
        if (!warp_row_arrived(src, row_word, uint(c.y))) continue;
        ++rows;
        arrived |= 1u << k;
        if (depth_test && !(same_ray && k == samples.exact)) {
          const ivec2 t = warp_depth_texel(src, c);
          const float ds = texelFetch(traced_depth0, t, 0).r;
          if (!(ds > 0.0)) continue;
          if (!(abs(dot(n_old, warp_depth_point(src, t, ds, pc.near_plane) - p_old)) <= tolerance)) continue;
        }
        const uint bit = warp_sample_mask_bit(src, c);
        masks[k] = warp_sample_mask(src, vis0[bit >> 5], bit);
        used |= 1u << k;
        if ((src.flags & kClientSourceHasEdges) != 0u) {
          const uint edge_bit = warp_edge_mask_bit(src, c);
          marks |= warp_sample_mask(src, vis0[edge_bit >> 5], edge_bit);
        }
      }
      if (rows == 0u) {
        status = kClientStatusMissingRow;
      } else if (used == 0u) {
        status = kClientStatusDisoccluded;
      } else {
        const WarpVote vote = warp_vote_band(
            warp_vote_fields(samples, masks, used, pc.soft_lights, pc.soft_edge_lights, pc.light_count), marks);
        value = vote.value;
        undecided = ~vote.agree & pc.unknown_mask;
        // warp.comp's refined soft shares (look_up), where every 2x2 sample that arrived was used.
        if ((pc.flags & kClientWarpSoftRefine) != 0u && used == arrived &&
            (src.flags & kClientSourceHasShares) != 0u) {
          refined = warp_soft_blend(samples, 0u, src, masks, used, value, vote.exact, pc.soft_lights,
                                    pc.soft_refine_bits, pc.light_count);
        }
      }
    }
    const bool known = status == kClientStatusKnown;
    // Motion (warp.comp's rule): bits something moved since the traced scene time may have changed.
    const uint moved_bits = known && (pc.flags & kClientWarpMotion) != 0u ? motion_unknown_bits(0u, p) : 0u;
    mask = value;
    if (!known || (undecided | moved_bits) != 0u) {  // the cost this mode saves: most pixels skip the shadow maps
      const uint from_shadow = undecided | moved_bits;
      // A known pixel takes only these bits from the maps: only their lights are looked up.
      const uint shadow = shadow_lookup_fields(pc, shadow_atlas, p, n, (pc.near_plane / d) * pc.pixel_tangent,
                                               known ? from_shadow : 0xFFFFFFFFu).mask;
      mask = known ? (value & ~from_shadow) | (shadow & from_shadow) : shadow;
      refined = known ? soft_refine_drop(refined, from_shadow, pc.soft_lights, pc.light_count)
                      : kClientSoftRefineNoneAll;
      status |= !known ? kClientForwardStatusShadowFill : undecided != 0u ? kClientForwardStatusShadowEdge : 0u;
      if (moved_bits != 0u) status |= kClientForwardStatusMotion;
    }
  } else if (shading.mode == kClientForwardShadowMaps) {
    radiance = shade_local(p, n, albedo, (pc.near_plane / d) * pc.pixel_tangent, mask);
    shaded = true;
  }
  if (!shaded) {
    radiance = (shading.flags & kClientShadingLightSlots) != 0u
                   ? shade_radiance_slots(p, n, albedo, mask, shading.light_count, shading.soft_lights,
                                          vec3(shading.slot_origin_mm[0], shading.slot_origin_mm[1],
                                               shading.slot_origin_mm[2]))
                   : shade_radiance(p, n, albedo, mask, shading.light_count, shading.soft_lights, refined);
  }
  vec3 display = encode_radiance(radiance, shading.exposure);
  if ((shading.flags & kClientShadingSwapRedBlue) != 0u) display = display.bgr;
  out_colour = vec4(display, 1.0);
#if DHR_FORWARD_STATUS
  out_status = status;
#endif
#if DHR_FORWARD_MASK
  out_mask = mask;
#endif
}
