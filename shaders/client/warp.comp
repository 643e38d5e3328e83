#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shaders/shader_interface.h"
#include "client/float3.h"

// Warp: each display pixel's surface point, reconstructed from this frame's depth, is projected into the old
// guard-banded camera a visibility buffer was traced for, and that buffer's masks around the lookup are taken.
//   nearest (the paper): the one old pixel under the lookup (floor of the continuous coordinate);
//   bilinear: the 2x2 old pixels around it; bits they all agree on are taken, the others by a bilinear vote
//     (or, with kClientWarpShadowEdges, from the shadow maps);
//   depth test: an old pixel whose surface (its depth, rendered by the client for the traced camera) lies off
//     the tangent plane of this pixel's surface saw something else there and is not used; when no sample is
//     left the pixel is disoccluded.
// Source 0 is this eye's newest buffer; a pixel it cannot fill tries source 1 (the other eye's newest), then
// source 2 (this eye's previous buffer, kClientWarpOlderBuffer), then the nearest old pixel of source 0 whose
// surface lies on this pixel's tangent plane (kClientWarpNeighbourFill, needs the depth test), then the shadow
// maps (kClientWarpShadowFill), else it takes all light bits ("taken as lit").
// xrclient/render/warp_reference.cpp is the CPU reference; the decisions have the same precedence.
// All positions are eye-relative: only small numbers reach the GPU.
layout(local_size_x = kClientWarpGroupSize, local_size_y = kClientWarpGroupSize) in;

layout(set = 0, binding = kClientWarpBindingDepth) uniform sampler2D depth_texture;
layout(set = 0, binding = kClientWarpBindingNormal) uniform sampler2D normal_texture;
layout(set = 0, binding = kClientWarpBindingVisibility0, std430) readonly buffer Visibility0 { uint vis0[]; };
layout(set = 0, binding = kClientWarpBindingRowValid0, std430) readonly buffer RowValid0 { uint rows0[]; };
layout(set = 0, binding = kClientWarpBindingOldDepth0) uniform sampler2D old_depth0;
layout(set = 0, binding = kClientWarpBindingVisibility1, std430) readonly buffer Visibility1 { uint vis1[]; };
layout(set = 0, binding = kClientWarpBindingRowValid1, std430) readonly buffer RowValid1 { uint rows1[]; };
layout(set = 0, binding = kClientWarpBindingOldDepth1) uniform sampler2D old_depth1;
layout(set = 0, binding = kClientWarpBindingVisibility2, std430) readonly buffer Visibility2 { uint vis2[]; };
layout(set = 0, binding = kClientWarpBindingRowValid2, std430) readonly buffer RowValid2 { uint rows2[]; };
layout(set = 0, binding = kClientWarpBindingOldDepth2) uniform sampler2D old_depth2;
layout(set = 0, binding = kClientWarpBindingMask, r32ui) uniform writeonly uimage2D mask_image;
layout(set = 0, binding = kClientWarpBindingStatus, r32ui) uniform writeonly uimage2D status_image;  // optional
layout(set = 0, binding = kClientWarpBindingMotion, rg32f) uniform writeonly image2D motion_image;
layout(set = 0, binding = kClientWarpBindingSoft, r32ui) uniform writeonly uimage2D soft_image;  // optional
layout(set = 0, binding = kClientWarpBindingCounters, std430) buffer Counters { uint counters[]; };
layout(set = 0, binding = kClientWarpBindingParams, std430) restrict readonly buffer Params { ClientWarpParams pc; };
layout(set = 0, binding = kClientWarpBindingShadowMap) uniform sampler2D shadow_atlas;
// The lights and their shadow-map tiles are declared by the helpers (client/light_buffer.h, shadow_lookup.h).
#define DHR_LIGHT_BUFFER_SET 0
#define DHR_LIGHT_BUFFER_BINDING kClientWarpBindingLights
#define DHR_SHADOW_LIGHT_BUFFER_SET 0
#define DHR_SHADOW_LIGHT_BUFFER_BINDING kClientWarpBindingShadowLights
#include "client/shadow_lookup.h"
#include "client/paper_warp.h"
#include "client/bilinear_warp.h"
#define DHR_MOTION_BUFFER_SET 0
#define DHR_MOTION_BUFFER_BINDING kClientWarpBindingMoved
#include "client/motion_rule.h"

// Source s is dynamically uniform: these selections do not diverge.
uint vis_word(uint s, uint index) { return s == 0u ? vis0[index] : s == 1u ? vis1[index] : vis2[index]; }
uint warp_share_load(uint source, uint word) { return vis_word(source, word); }  // bilinear_warp.h's band shares
bool row_ok(uint s, uint row) {
  if ((pc.source[s].flags & kClientSourceHasRowValidity) == 0u) return true;
  const uint word = s == 0u ? rows0[row >> 5] : s == 1u ? rows1[row >> 5] : rows2[row >> 5];
  return ((word >> (row & 31u)) & 1u) != 0u;
}
float old_depth_at(uint s, ivec2 c) {  // c: a traced-depth texel (warp_depth_texel)
  return s == 0u ? texelFetch(old_depth0, c, 0).r
                 : s == 1u ? texelFetch(old_depth1, c, 0).r : texelFetch(old_depth2, c, 0).r;
}
uint old_mask(uint s, int a, int b) {
  const uint bit = warp_sample_mask_bit(pc.source[s], ivec2(a, b));
  return warp_sample_mask(pc.source[s], vis_word(s, bit >> 5), bit);
}

// What one source says about a pixel.
struct Lookup {
  uint status;  // kClientStatus*
  uint agree;   // over the used samples: bits all of them agree on (their value is in `value`)
  uint value;   // agreed bits: their value; other bits: the bilinear vote
  bool exact;   // bilinear: the lookup is at an old pixel centre whose sample is used: value is its mask
  vec2 pixel;   // continuous lookup coordinate
  uint refined; // kClientWarpSoftRefine: the soft fields' refined shares (warp_soft_blend), else none
};

Lookup look_up(uint s, float d, vec2 centre, vec3 n_world) {
  Lookup r;
  r.refined = kClientSoftRefineNoneAll;
  r.agree = 0u;
  r.value = 0u;
  r.exact = false;
  const vec3 ray = v3(pc.source[s].ray0) + centre.x * v3(pc.source[s].ray_dx) + centre.y * v3(pc.source[s].ray_dy);
  const vec3 p_old = (pc.near_plane / d) * ray + v3(pc.source[s].trans);
  const float depth_old = -p_old.z;
  const float px = pc.source[s].old_px_scale * (p_old.x / depth_old) + pc.source[s].old_px_offset;
  const float py = pc.source[s].old_py_scale * (p_old.y / depth_old) + pc.source[s].old_py_offset;
  r.pixel = vec2(px, py);
  const bool inside = px >= 0.0 && py >= 0.0 && px < float(pc.source[s].old_width) && py < float(pc.source[s].old_height);
  if ((pc.source[s].flags & kClientSourceHasVisibility) == 0u) {
    r.status = kClientStatusNoData;
    return r;
  }
  if (!(depth_old > pc.min_depth)) {
    r.status = kClientStatusBehind;
    return r;
  }
  if (!inside) {
    r.status = kClientStatusOutside;
    return r;
  }
  const bool bilinear = (pc.flags & kClientWarpBilinear) != 0u;
  const bool depth_test = (pc.flags & kClientWarpDepthTest) != 0u && (pc.source[s].flags & kClientSourceHasDepth) != 0u;
  vec3 n_old = vec3(0.0);
  if (depth_test) {
    n_old = vec3(pc.source[s].rot[0] * n_world.x + pc.source[s].rot[1] * n_world.y + pc.source[s].rot[2] * n_world.z,
                 pc.source[s].rot[3] * n_world.x + pc.source[s].rot[4] * n_world.y + pc.source[s].rot[5] * n_world.z,
                 pc.source[s].rot[6] * n_world.x + pc.source[s].rot[7] * n_world.y + pc.source[s].rot[8] * n_world.z);
  }
  const float tolerance = pc.plane_tolerance_rel * depth_old + pc.plane_tolerance_abs;
  const WarpSamples samples = warp_samples(r.pixel, bilinear);
  uint rows = 0u, used = 0u, marks = 0u, arrived = 0u;
  uint masks[4];
  // Bilinear: a lookup within kClientWarpExactLookup of an old pixel centre (samples.exact) takes that pixel's
  // bit as exact when it is used. Traced from this very eye position, that pixel's ray is this pixel's ray:
  // its sample skips the depth test (two rasterizations of one ray may disagree at a silhouette; the traced bit
  // is right). From elsewhere the old ray may have hit an occluder, and the depth test decides.
  const bool same_ray = samples.centred && (pc.source[s].flags & kClientSourceSameEye) != 0u;
  for (int k = 0; k < 4; ++k) {
    masks[k] = 0u;
    if (k >= samples.count) continue;
    const ivec2 c = warp_sample_pixel(samples, k);
    if (!warp_sample_in_buffer(pc.source[s], c)) continue;
    if (!row_ok(s, uint(c.y))) continue;
    ++rows;
    arrived |= 1u << k;
    if (depth_test && !(same_ray && k == samples.exact)) {
      const ivec2 t = warp_depth_texel(pc.source[s], c);
      const float ds = old_depth_at(s, t);
      if (!(ds > 0.0)) continue;
      const vec3 q = warp_depth_point(pc.source[s], t, ds, pc.near_plane);
      if (!(abs(dot(n_old, q - p_old)) <= tolerance)) continue;
    }
    masks[k] = old_mask(s, c.x, c.y);
    used |= 1u << k;
    if ((pc.source[s].flags & kClientSourceHasEdges) != 0u) {
      const uint bit = warp_edge_mask_bit(pc.source[s], c);
      marks |= warp_sample_mask(pc.source[s], vis_word(s, bit >> 5), bit);
    }
  }
  if (rows == 0u) {
    r.status = kClientStatusMissingRow;
    return r;
  }
  if (used == 0u) {
    r.status = kClientStatusDisoccluded;
    return r;
  }
  r.status = kClientStatusKnown;
  const WarpVote vote = warp_vote_band(
      warp_vote_fields(samples, masks, used, pc.soft_lights, pc.soft_edge_lights, pc.light_count), marks);
  r.agree = vote.agree;
  r.value = vote.value;
  r.exact = vote.exact;
  // Refined soft shares from the used samples' band shares, where the depth test used every 2x2 sample that arrived
  // (a rejected one: a silhouette, whose far side must not be mixed in).
  if ((pc.flags & kClientWarpSoftRefine) != 0u && bilinear && used == arrived &&
      (pc.source[s].flags & kClientSourceHasShares) != 0u) {
    r.refined = warp_soft_blend(samples, s, pc.source[s], masks, used, vote.value, vote.exact, pc.soft_lights,
                                pc.soft_refine_bits, pc.light_count);
  }
  return r;
}

// Neighbour fill: the old pixels of source 0 within kClientWarpNeighbourRadius of the lookup's pixel whose
// row arrived and whose surface lies on this pixel's tangent plane (the depth test's plane check); the one
// whose centre is nearest the lookup gives its whole mask (ties: the first in row-major order).
// Needs the source's traced depth; the lookup must not be behind the old eye.
Lookup look_up_neighbours(uint s, float d, vec2 centre, vec3 n_world) {
  Lookup r;
  r.refined = kClientSoftRefineNoneAll;
  r.status = kClientStatusDisoccluded;
  r.agree = 0u;
  r.value = 0u;
  r.exact = false;
  const vec3 ray = v3(pc.source[s].ray0) + centre.x * v3(pc.source[s].ray_dx) + centre.y * v3(pc.source[s].ray_dy);
  const vec3 p_old = (pc.near_plane / d) * ray + v3(pc.source[s].trans);
  const float depth_old = -p_old.z;
  const float px = pc.source[s].old_px_scale * (p_old.x / depth_old) + pc.source[s].old_px_offset;
  const float py = pc.source[s].old_py_scale * (p_old.y / depth_old) + pc.source[s].old_py_offset;
  r.pixel = vec2(px, py);
  if (!(depth_old > pc.min_depth)) return r;
  const vec3 n_old =
      vec3(pc.source[s].rot[0] * n_world.x + pc.source[s].rot[1] * n_world.y + pc.source[s].rot[2] * n_world.z,
           pc.source[s].rot[3] * n_world.x + pc.source[s].rot[4] * n_world.y + pc.source[s].rot[5] * n_world.z,
           pc.source[s].rot[6] * n_world.x + pc.source[s].rot[7] * n_world.y + pc.source[s].rot[8] * n_world.z);
  const float tolerance = pc.plane_tolerance_rel * depth_old + pc.plane_tolerance_abs;
  // Far outside the buffer the window misses it; clamping first keeps the integer conversion in range.
  const int ci = int(floor(clamp(px, -64.0, float(pc.source[s].old_width) + 64.0)));
  const int cj = int(floor(clamp(py, -64.0, float(pc.source[s].old_height) + 64.0)));
  float best = 1e30;
  int best_a = -1, best_b = -1;
  for (int b = cj - kClientWarpNeighbourRadius; b <= cj + kClientWarpNeighbourRadius; ++b) {
    if (b < 0 || b >= int(pc.source[s].old_height) || !row_ok(s, uint(b))) continue;
    for (int a = ci - kClientWarpNeighbourRadius; a <= ci + kClientWarpNeighbourRadius; ++a) {
      if (a < 0 || a >= int(pc.source[s].old_width)) continue;
      const ivec2 t = warp_depth_texel(pc.source[s], ivec2(a, b));
      const float ds = old_depth_at(s, t);
      if (!(ds > 0.0)) continue;
      const vec3 q = warp_depth_point(pc.source[s], t, ds, pc.near_plane);
      if (!(abs(dot(n_old, q - p_old)) <= tolerance)) continue;
      const float ex = float(a) + 0.5 - px;
      const float ey = float(b) + 0.5 - py;
      const float dist = ex * ex + ey * ey;
      if (dist < best) {
        best = dist;
        best_a = a;
        best_b = b;
      }
    }
  }
  if (best_a < 0) return r;
  r.status = kClientStatusKnown;
  r.agree = 0xFFFFFFFFu;
  r.value = old_mask(s, best_a, best_b);
  return r;
}

void main() {
  const uvec2 id = gl_GlobalInvocationID.xy;
  const bool in_image = id.x < pc.width && id.y < pc.height;
  uint status = kClientStatusCount;  // outside the image: counted nowhere
  uint fill = kClientFillNone;
  bool edge_from_shadow = false;
  bool overridden = false;  // a confident shadow-map bit replaced a bit the samples agreed on
  bool motion_unknown = false;  // motion made some of the chosen source's bits unknown
  const uint ingredients = kClientWarpBilinear | kClientWarpDepthTest | kClientWarpShadowFill | kClientWarpShadowEdges |
                           kClientWarpShadowFirst | kClientWarpOlderBuffer | kClientWarpNeighbourFill | kClientWarpMotion;
  const bool paper = (pc.flags & ingredients) == 0u && (pc.source[1].flags & kClientSourceHasVisibility) == 0u;
  if (in_image && paper) {  // dynamically uniform
    const vec2 centre = vec2(id) + 0.5;
    const float d = texelFetch(depth_texture, ivec2(id), 0).r;
    const PaperWarpLookup at = paper_warp_lookup(pc, centre, d);
    const uint row_word = paper_warp_reads_rows(pc) ? rows0[at.row >> 5] : 0u;
    uint mask;
    vec2 motion;
    status = paper_warp(pc, centre, d, at, row_word, vis0[at.mask_bit >> 5], mask, motion);
    imageStore(mask_image, ivec2(id), uvec4(mask, 0u, 0u, 0u));
    if ((pc.flags & kClientWarpWriteStatus) != 0u) imageStore(status_image, ivec2(id), uvec4(status, 0u, 0u, 0u));
    if ((pc.flags & kClientWarpWriteMotion) != 0u) imageStore(motion_image, ivec2(id), vec4(motion, 0.0, 0.0));
    if ((pc.flags & kClientWarpSoftRefine) != 0u) imageStore(soft_image, ivec2(id), uvec4(kClientSoftRefineNoneAll));
  } else if (in_image) {
    const float d = texelFetch(depth_texture, ivec2(id), 0).r;
    const vec2 centre = vec2(id) + 0.5;
    uint mask = pc.unknown_mask;
    uint refined = kClientSoftRefineNoneAll;
    vec2 motion = vec2(0.0);
    if (!(d > 0.0)) {
      status = kClientStatusBackground;
    } else {
      // The normal only where something reads it (the depth test, shadow lookups).
      const bool needs_normal =
          (pc.flags & (kClientWarpDepthTest | kClientWarpShadowFill | kClientWarpShadowEdges | kClientWarpShadowFirst)) != 0u;
      const vec3 n = needs_normal ? normalize(texelFetch(normal_texture, ivec2(id), 0).xyz) : vec3(0.0, 0.0, 1.0);
      Lookup own = look_up(0u, d, centre, n);
      status = own.status;
      Lookup chosen = own;
      uint chosen_source = 0u;
      if (own.status != kClientStatusKnown && (pc.source[1].flags & kClientSourceHasVisibility) != 0u) {
        const Lookup other = look_up(1u, d, centre, n);
        if (other.status == kClientStatusKnown) {
          chosen = other;
          chosen_source = 1u;
          fill = kClientFillOtherEye;
        }
      }
      if (own.status != kClientStatusKnown && fill == kClientFillNone && (pc.flags & kClientWarpOlderBuffer) != 0u &&
          (pc.source[2].flags & kClientSourceHasVisibility) != 0u) {
        const Lookup older = look_up(2u, d, centre, n);
        if (older.status == kClientStatusKnown) {
          chosen = older;
          chosen_source = 2u;
          fill = kClientFillOlder;
        }
      }
      if (fill == kClientFillNone && (pc.flags & kClientWarpNeighbourFill) != 0u &&
          (own.status == kClientStatusOutside || own.status == kClientStatusMissingRow ||
           own.status == kClientStatusDisoccluded) &&
          (pc.flags & kClientWarpDepthTest) != 0u && (pc.source[0].flags & kClientSourceHasDepth) != 0u) {
        const Lookup neighbour = look_up_neighbours(0u, d, centre, n);
        if (neighbour.status == kClientStatusKnown) {
          chosen = neighbour;
          fill = kClientFillNeighbour;
        }
      }
      const bool have = status == kClientStatusKnown || fill != kClientFillNone;
      const bool first = (pc.flags & kClientWarpShadowFirst) != 0u;
      const vec3 p = (pc.near_plane / d) *
                     (v3(pc.world_ray0) + centre.x * v3(pc.world_ray_dx) + centre.y * v3(pc.world_ray_dy));
      // Motion: the chosen source's bits that something moved since its scene time may have changed.
      const uint moved_bits = have && (pc.flags & kClientWarpMotion) != 0u ? motion_unknown_bits(chosen_source, p) : 0u;
      const uint shadow_settings = kClientWarpShadowFill | kClientWarpShadowEdges | kClientWarpShadowFirst;
      const uint to_shadow = (pc.flags & shadow_settings) != 0u ? moved_bits : 0u;
      motion_unknown = moved_bits != 0u;
      const uint undecided = have ? ~chosen.agree & pc.unknown_mask : 0u;
      const bool need_shadow = have ? (first && !chosen.exact) || ((pc.flags & kClientWarpShadowEdges) != 0u && undecided != 0u) ||
                                          to_shadow != 0u
                                    : (pc.flags & kClientWarpShadowFill) != 0u;
      ShadowLookup shadow;
      shadow.mask = 0u;
      shadow.confident = 0u;
      if (need_shadow) {
        // Without shadow-first a known pixel takes only its undecided and motion bits from the maps: only their
        // lights are looked up.
        const uint wanted = have && !first ? ((pc.flags & kClientWarpShadowEdges) != 0u ? undecided : 0u) | to_shadow
                                           : 0xFFFFFFFFu;
        shadow = shadow_lookup_fields(pc, shadow_atlas, p, n, (pc.near_plane / d) * pc.pixel_tangent, wanted);
      }
      if (have) {
        // Bits the samples agree on keep their value unless the shadow maps are confident (shadow-first);
        // the others take the shadow maps (shadow edges) or the vote.
        const bool edges = (pc.flags & kClientWarpShadowEdges) != 0u;
        const uint from_shadow = (first && !chosen.exact ? shadow.confident : 0u) | (edges ? undecided : 0u) | to_shadow;
        mask = (chosen.value & ~from_shadow) | (shadow.mask & from_shadow);
        refined = soft_refine_drop(chosen.refined, from_shadow, pc.soft_lights, pc.light_count);
        edge_from_shadow = edges && undecided != 0u;
        overridden = (from_shadow & ~undecided & ~to_shadow & (chosen.value ^ shadow.mask) & pc.unknown_mask) != 0u;
      } else if ((pc.flags & kClientWarpShadowFill) != 0u) {
        mask = shadow.mask;
        fill = kClientFillShadowMap;
      }
      const bool motion_valid = status == kClientStatusKnown || status == kClientStatusOutside ||
                                status == kClientStatusMissingRow || status == kClientStatusDisoccluded;
      if (motion_valid) {
        const vec2 still = vec2(pc.ident_px_scale * centre.x + pc.ident_px_offset,
                                pc.ident_py_scale * centre.y + pc.ident_py_offset);
        motion = own.pixel - still;
      }
    }
    imageStore(mask_image, ivec2(id), uvec4(mask, 0u, 0u, 0u));
    if ((pc.flags & kClientWarpWriteStatus) != 0u) {
      imageStore(status_image, ivec2(id), uvec4(status | (fill << 8), 0u, 0u, 0u));
    }
    if ((pc.flags & kClientWarpWriteMotion) != 0u) {
      imageStore(motion_image, ivec2(id), vec4(motion, 0.0, 0.0));
    }
    if ((pc.flags & kClientWarpSoftRefine) != 0u) imageStore(soft_image, ivec2(id), uvec4(refined, 0u, 0u, 0u));
  }

  // Counts: one subgroup sum per word of one-hot values packed in 10-bit fields, then the elected lane adds
  // them to its bucket (8 horizontally adjacent workgroups, at most 512 pixels: no field overflows); the
  // host unpacks and sums the buckets. Buckets instead of one counter per field: with every workgroup
  // hitting the same words the atomics serialize (on lavapipe they cost a third of the pass).
  uint words[kClientCountWords];
  for (uint w = 0u; w < kClientCountWords; ++w) words[w] = 0u;
  if (status < kClientStatusCount) words[status / 3u] += 1u << (10u * (status % 3u));
  if (fill == kClientFillOtherEye) words[kClientCountOtherEye / 3u] += 1u << (10u * (kClientCountOtherEye % 3u));
  if (fill == kClientFillShadowMap) words[kClientCountShadowMap / 3u] += 1u << (10u * (kClientCountShadowMap % 3u));
  if (fill == kClientFillOlder) words[kClientCountOlder / 3u] += 1u << (10u * (kClientCountOlder % 3u));
  if (fill == kClientFillNeighbour) words[kClientCountNeighbour / 3u] += 1u << (10u * (kClientCountNeighbour % 3u));
  if (edge_from_shadow) words[kClientCountEdgeShadowMap / 3u] += 1u << (10u * (kClientCountEdgeShadowMap % 3u));
  if (overridden) words[kClientCountShadowOverride / 3u] += 1u << (10u * (kClientCountShadowOverride % 3u));
  if (motion_unknown) words[kClientCountMotion / 3u] += 1u << (10u * (kClientCountMotion % 3u));
  // The paper's rule yields statuses 0-5 only: the first two words (a subgroup sum each costs on lavapipe).
  const uint used_words = paper ? 2u : kClientCountWords;
  uint sums[kClientCountWords];
  for (uint w = 0u; w < kClientCountWords; ++w) sums[w] = w < used_words ? subgroupAdd(words[w]) : 0u;
  if (subgroupElect()) {
    const uint buckets_x = (gl_NumWorkGroups.x + kClientCountBucketGroups - 1u) / kClientCountBucketGroups;
    const uint bucket = kClientCountWords * (gl_WorkGroupID.y * buckets_x + gl_WorkGroupID.x / kClientCountBucketGroups);
    for (uint w = 0u; w < used_words; ++w) {
      if (sums[w] != 0u) atomicAdd(counters[bucket + w], sums[w]);
    }
  }
}
