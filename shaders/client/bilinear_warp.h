// The warp's sampling of one old buffer and its agreement rule (GLSL; included by warp.comp and
// client/forward_body.h): one definition for the compute warp and the forward pass. The CPU reference is
// render/warp_reference.cpp. Everything comes as arguments: the source (ClientWarpSource) and the lookup's
// continuous coordinate in its buffer; the includer loads the samples' row validity and masks from its own
// buffers (GLSL cannot pass them) and decides which samples are used (row arrived, depth test):
//   const WarpSamples s = warp_samples(pixel, bilinear);
//   for (int k = 0; k < s.count; ++k) { const ivec2 c = warp_sample_pixel(s, k); if (!warp_sample_in_buffer(src, c))
//     continue; ... masks[k] = warp_sample_mask(src, word, warp_sample_mask_bit(src, c)); used |= 1u << k; }
//   const WarpVote v = warp_vote_fields(s, masks, used, soft_lights, edge_lights, light_count);  // used != 0
// and, with the source's edge band, warp_vote_band(v, the OR of the used samples' marks).
#ifndef DHR_BILINEAR_WARP_H
#define DHR_BILINEAR_WARP_H

#include "shaders/shader_interface.h"
#include "client/visibility_field.h"

// The old pixels a lookup reads. Nearest (the paper): the one under the lookup; bilinear: the 2x2 around
// pixel - 0.5 (one of them is the nearest's), sample k at first + (k & 1, k >> 1).
struct WarpSamples {
  ivec2 first;
  vec2 frac;     // bilinear: the lookup between the samples' centres (the weights)
  int count;     // 1 or 4
  int exact;     // the sample whose centre is nearest the lookup
  bool centred;  // bilinear: the lookup lies within kClientWarpExactLookup of that centre
};

WarpSamples warp_samples(vec2 pixel, bool bilinear) {
  WarpSamples s;
  const float bx = bilinear ? pixel.x - 0.5 : pixel.x;
  const float by = bilinear ? pixel.y - 0.5 : pixel.y;
  s.first = ivec2(int(floor(bx)), int(floor(by)));
  s.frac = vec2(bx - float(s.first.x), by - float(s.first.y));
  s.count = bilinear ? 4 : 1;
  s.exact = (s.frac.x < 0.5 ? 0 : 1) + 2 * (s.frac.y < 0.5 ? 0 : 1);
  s.centred = bilinear && min(s.frac.x, 1.0 - s.frac.x) <= kClientWarpExactLookup &&
              min(s.frac.y, 1.0 - s.frac.y) <= kClientWarpExactLookup;
  return s;
}

ivec2 warp_sample_pixel(WarpSamples s, int k) { return s.first + ivec2(k & 1, k >> 1); }

float warp_sample_weight(WarpSamples s, int k) {
  if (s.count == 1) return 1.0;
  return ((k & 1) != 0 ? s.frac.x : 1.0 - s.frac.x) * ((k >> 1) != 0 ? s.frac.y : 1.0 - s.frac.y);
}

bool warp_sample_in_buffer(ClientWarpSource src, ivec2 c) {
  return c.x >= 0 && c.y >= 0 && c.x < int(src.old_width) && c.y < int(src.old_height);
}

// Whether row `row` arrived, given word row >> 5 of the source's row validity (any value without validity).
bool warp_row_arrived(ClientWarpSource src, uint row_word, uint row) {
  return (src.flags & kClientSourceHasRowValidity) == 0u || ((row_word >> (row & 31u)) & 1u) != 0u;
}

// The first bit of old pixel c's mask in the source's packed masks; the mask is in word bit >> 5.
uint warp_sample_mask_bit(ClientWarpSource src, ivec2 c) {
  return (uint(c.y) * src.old_width + uint(c.x)) * src.mask_bits;
}

uint warp_sample_mask(ClientWarpSource src, uint word, uint bit) {
  const uint width_mask = src.mask_bits >= 32u ? 0xFFFFFFFFu : (1u << src.mask_bits) - 1u;
  return (word >> (bit & 31u)) & width_mask;
}

// The edge band (kClientSourceHasEdges; render/warp_edges.hpp): the first bit of old pixel c's marks (the hard-light
// bits some arrived old pixel within the band disagrees on), in the source's buffer after its masks; the includer
// loads word bit >> 5 and reads it with warp_sample_mask.
uint warp_edge_mask_bit(ClientWarpSource src, ivec2 c) { return src.edge_word * 32u + warp_sample_mask_bit(src, c); }

// The depth test (kClientWarpDepthTest, kClientSourceHasDepth): the traced-depth texel that holds old pixel c's
// depth, and the old surface point (old eye space) that texel's depth ds shows: along the ray through the
// texel's centre, old pixel coordinate (t + 0.5) * depth_scale (the old pixel's own centre at depth_scale 1).
ivec2 warp_depth_texel(ClientWarpSource src, ivec2 c) { return c / int(max(src.depth_scale, 1u)); }

vec3 warp_depth_point(ClientWarpSource src, ivec2 t, float ds, float near_plane) {
  const float k = float(max(src.depth_scale, 1u));
  return (near_plane / ds) * vec3(src.old_tan_left + (float(t.x) + 0.5) * k * src.old_tan_step_x,
                                  src.old_tan_up - (float(t.y) + 0.5) * k * src.old_tan_step_y, -1.0);
}

// What the used samples say.
struct WarpVote {
  uint agree;  // bits all used samples agree on (their value is in `value`)
  uint value;  // agreed bits: their value; other bits: the bilinear vote (set when 2 * the weight of the used
               // samples with the bit >= the weight of the used samples)
  bool exact;  // centred on a used sample: `value` is its mask, every bit agreed
};

// masks[k]: sample k's mask where bit k of `used` is set (used != 0).
WarpVote warp_vote(WarpSamples s, uint masks[4], uint used) {
  WarpVote v;
  v.exact = false;
  if (s.centred && ((used >> s.exact) & 1u) != 0u) {
    v.exact = true;
    v.agree = 0xFFFFFFFFu;
    v.value = masks[s.exact];
    return v;
  }
  uint and_m = 0xFFFFFFFFu, or_m = 0u;
  for (int k = 0; k < s.count; ++k) {
    if (((used >> k) & 1u) == 0u) continue;
    and_m &= masks[k];
    or_m |= masks[k];
  }
  v.agree = ~(and_m ^ or_m);
  v.value = and_m;
  uint open = or_m & ~and_m;
  if (open != 0u) {
    float total = 0.0;
    for (int k = 0; k < s.count; ++k) total += ((used >> k) & 1u) != 0u ? warp_sample_weight(s, k) : 0.0;
    while (open != 0u) {
      const int bit = findLSB(open);
      open &= open - 1u;
      float set = 0.0;
      for (int k = 0; k < s.count; ++k) {
        set += (((used >> k) & 1u) != 0u && ((masks[k] >> bit) & 1u) != 0u) ? warp_sample_weight(s, k) : 0.0;
      }
      if (2.0 * set >= total) v.value |= 1u << bit;
    }
  }
  return v;
}

// warp_vote, then each soft field (soft_lights, the first light_count lights' fields) the used samples disagree on
// takes the bilinear blend of their levels, sum w_k level_k / 7 / sum w_k, quantized to the nearest level: a level
// is a share of the light, so between two samples it is meaningful to interpolate (a hard bit's vote is not). The
// field counts as agreed (the blend is the server's answer) unless it is one of edge_lights (a sun's: its penumbra
// is a pixel or two wide) and the used samples' levels span more than kClientWarpSoftEdgeSpread levels: that is an
// edge, which the shadow maps decide as they do a hard bit's. A light with a wide penumbra (rect, disk, sphere)
// keeps the blend there too: on living_room_area the maps' PCSS did no better at such 2x2s (docs/client.md).
WarpVote warp_vote_fields(WarpSamples s, uint masks[4], uint used, uint soft_lights, uint edge_lights,
                          uint light_count) {
  WarpVote v = warp_vote(s, masks, used);
  if (soft_lights == 0u || v.exact) return v;
  float total = 0.0;
  for (int k = 0; k < s.count; ++k) total += ((used >> k) & 1u) != 0u ? warp_sample_weight(s, k) : 0.0;
  uint offset = 0u;
  for (uint i = 0u; i < light_count; ++i) {
    const uint bits = field_bits(soft_lights, i);
    const uint field = ((1u << bits) - 1u) << offset;
    if (bits > 1u && (~v.agree & field) != 0u) {
      float blend = 0.0, lowest = 1.0, highest = 0.0;
      for (int k = 0; k < s.count; ++k) {
        if (((used >> k) & 1u) == 0u) continue;
        const float f = field_visibility(masks[k], offset, bits);
        blend += warp_sample_weight(s, k) * f;
        lowest = min(lowest, f);
        highest = max(highest, f);
      }
      v.value = (v.value & ~field) | field_from_fraction(blend / total, offset, bits);
      const uint spread = uint(round((highest - lowest) * float(kClientSoftLevels - 1u)));
      if (((edge_lights >> i) & 1u) == 0u || spread <= kClientWarpSoftEdgeSpread) v.agree |= field;
    }
    offset += bits;
  }
  return v;
}

// Word `word` of source `source`'s buffer: the includer defines it (GLSL cannot pass buffers), for the band shares'
// table (kClientSourceHasShares; render/soft_bands.hpp's SoftBandTable).
uint warp_share_load(uint source, uint word);

// The first word of old pixel c's cell in the band shares' table.
uint warp_share_cell_word(ClientWarpSource src, ivec2 c) {
  const uint cell = (uint(c.y) >> src.share_cell_shift) * src.share_columns + (uint(c.x) >> src.share_cell_shift);
  return src.share_word + cell * kClientSoftBandCellWords;
}

// Refined soft shares (kClientWarpSoftRefine) at a bilinear lookup into source `source` (src) whose vote gave
// `value`: for each of the first kClientSoftRefineFields soft fields with a bit in soft_bits
// (ClientWarpParams::soft_refine_bits: not an edge light's, a sun's penumbra is a pixel or two wide), the bilinear
// blend of the used samples' band shares (their level's byte in their cell of the table, reconstructed once per
// source: render/soft_bands.hpp; a none byte: the sample's level) over the samples whose level lies within one level
// of the vote's (a jump of more, a contact shadow, is kept); an exact vote takes its sample's share alone. One byte
// per field, the share times kClientSoftRefineScale rounded; kClientSoftRefineNone where no such sample has a band
// share or weighs anything (the vote's level holds). The CPU twin is render/soft_refine.cpp's soft_blend.
uint warp_soft_blend(WarpSamples s, uint source, ClientWarpSource src, uint masks[4], uint used, uint value,
                     bool exact, uint soft_lights, uint soft_bits, uint light_count) {
  uint cells[4];
  for (int k = 0; k < 4; ++k) cells[k] = warp_share_cell_word(src, warp_sample_pixel(s, k));
  uint packed = kClientSoftRefineNoneAll;
  uint rank = 0u, offset = 0u;
  for (uint i = 0u; i < light_count && rank < kClientSoftRefineFields; ++i) {
    const uint bits = field_bits(soft_lights, i);
    const uint field = ((1u << bits) - 1u) << offset;
    // Only a sample at a middle level has a band share: a field whose used samples all lie at the bottom or the top
    // level (Gray codes 0 and 4) keeps the vote's level without the blend.
    bool middle = false;
    if (bits > 1u && (field & soft_bits) != 0u) {
      for (int k = 0; k < s.count; ++k) {
        const uint g = (masks[k] >> offset) & 7u;
        middle = middle || (((used >> uint(k)) & 1u) != 0u && g != 0u && g != 4u);
      }
    }
    if (middle) {
      const float centre = field_visibility(value, offset, bits);
      float sum = 0.0, total = 0.0;
      bool has_share = false;
      for (int k = 0; k < s.count; ++k) {
        if (((used >> uint(k)) & 1u) == 0u || (exact && k != s.exact)) continue;
        const float f = field_visibility(masks[k], offset, bits);
        if (abs(f - centre) * float(kClientSoftLevels - 1u) > 1.5) continue;
        const uint n = uint(round(f * float(kClientSoftLevels - 1u)));
        // The bottom and top levels have no band share (render/soft_bands.hpp): no load.
        const uint byte = n == 0u || n == kClientSoftLevels - 1u
                              ? kClientSoftRefineNone
                              : (warp_share_load(source, cells[k] + 2u * rank + n / 4u) >> (8u * (n % 4u))) & 0xFFu;
        const float share = byte == kClientSoftRefineNone ? f : float(byte) / float(kClientSoftRefineScale);
        const float w = exact ? 1.0 : warp_sample_weight(s, k);
        sum += w * share;
        total += w;
        has_share = has_share || byte != kClientSoftRefineNone;
      }
      if (has_share && total > 0.0) {
        const uint byte = uint(floor(clamp(sum / total, 0.0, 1.0) * float(kClientSoftRefineScale) + 0.5));
        packed = (packed & ~(0xFFu << (8u * rank))) | (byte << (8u * rank));
      }
    }
    if (bits > 1u) ++rank;
    offset += bits;
  }
  return packed;
}

// Clears (to kClientSoftRefineNone) the refined shares of the soft fields any of whose bits are in `bits` (taken
// from elsewhere than the samples: the shadow maps).
uint soft_refine_drop(uint packed, uint bits, uint soft_lights, uint light_count) {
  if (packed == kClientSoftRefineNoneAll || bits == 0u) return packed;  // the common case: nothing to drop
  uint offset = 0u, rank = 0u;
  for (uint i = 0u; i < light_count && rank < kClientSoftRefineFields; ++i) {
    const uint b = field_bits(soft_lights, i);
    if (b > 1u) {
      if ((bits & (((1u << b) - 1u) << offset)) != 0u) packed |= 0xFFu << (8u * rank);
      ++rank;
    }
    offset += b;
  }
  return packed;
}

// The vote with the bits the used samples' edge band marks (their OR) undecided; an exact lookup keeps its pixel's
// mask.
WarpVote warp_vote_band(WarpVote v, uint marks) {
  if (!v.exact) v.agree &= ~marks;
  return v;
}

#endif  // DHR_BILINEAR_WARP_H
