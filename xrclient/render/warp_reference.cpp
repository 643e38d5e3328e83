#include "render/warp_reference.hpp"

#include "render/soft_bands.hpp"
#include "render/soft_refine.hpp"
#include "render/warp_motion.hpp"

#include "render/light_layout.hpp"
#include "render/warp_edges.hpp"
#include "shaders/shader_interface.h"

#include <algorithm>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace dhr::render {
namespace {

// Distance of coordinate v from the nearest integer (the pixel boundaries).
double boundary_distance(double v) { return std::abs(v - std::round(v)); }

// How far (px) the inside/outside and floor decisions are from flipping.
double lookup_margin(const glm::dvec2& p, const Extent& extent) {
  const double w = extent.width, h = extent.height;
  const double out_x = p.x < 0.0 ? -p.x : (p.x >= w ? p.x - w : -1.0);
  const double out_y = p.y < 0.0 ? -p.y : (p.y >= h ? p.y - h : -1.0);
  if (out_x >= 0.0 || out_y >= 0.0) return std::max(out_x, out_y);  // outside: only the edge distance counts
  return std::min(boundary_distance(p.x), boundary_distance(p.y));
}

}  // namespace

Camera depth_camera(const Camera& traced, uint32_t scale) {
  if (scale == 0 || scale > 16) throw std::invalid_argument("depth_camera: scale must be 1 to 16");
  if (scale == 1) return traced;
  Camera c = traced;
  const Extent e = traced.extent;
  c.extent = Extent{(e.width + scale - 1) / scale, (e.height + scale - 1) / scale};
  const double step_x = traced.tangents.width() / e.width;
  const double step_y = traced.tangents.height() / e.height;
  c.tangents.right = traced.tangents.left + step_x * (static_cast<double>(c.extent.width) * scale);
  c.tangents.down = traced.tangents.up - step_y * (static_cast<double>(c.extent.height) * scale);
  return c;
}

uint64_t WarpCounts::surface() const { return unknown_surface() + (*this)[WarpStatus::kKnown]; }

bool same_eye(const Camera& display, const Camera& traced) {
  return glm::length(display.T_world_eye.position - traced.T_world_eye.position) <= 1e-9;
}

uint32_t unknown_mask(const VisibilityBuffer* visibility, std::span<const SceneLight> lights) {
  const uint32_t all = visibility != nullptr ? visibility->light_bits() : 0xFFFFFFFFu;
  const VisibilityLayout layout = layout_for_lights(lights.first(std::min<size_t>(lights.size(), kMaxLights)));
  return layout.any_soft() ? all & layout.all_lit() : all;
}

std::optional<std::string> validate_visibility_input(const Camera& traced, const VisibilityBuffer& visibility,
                                                     std::span<const uint8_t> row_valid) {
  if (auto err = validate_camera(traced)) return "traced camera: " + *err;
  if (traced.extent.width != visibility.width || traced.extent.height != visibility.height) {
    return "visibility buffer is " + std::to_string(visibility.width) + "x" + std::to_string(visibility.height) +
           " but its traced camera is " + std::to_string(traced.extent.width) + "x" +
           std::to_string(traced.extent.height);
  }
  if (visibility.width == 0 || visibility.height == 0 || visibility.width > kMaxBufferDimension ||
      visibility.height > kMaxBufferDimension) {
    return "visibility buffer size " + std::to_string(visibility.width) + "x" + std::to_string(visibility.height) +
           " is empty or exceeds " + std::to_string(kMaxBufferDimension);
  }
  if (visibility.light_count > kMaxLights) return "visibility buffer has more than 32 lights";
  if (!mask_width_from_bits(static_cast<uint32_t>(visibility.mask_bits))) return "visibility buffer mask width";
  if (visibility.data.size() != visibility.size_bytes()) {
    return "visibility buffer holds " + std::to_string(visibility.data.size()) + " bytes, expected " +
           std::to_string(visibility.size_bytes());
  }
  if (!row_valid.empty() && row_valid.size() != visibility.height) {
    return "row validity has " + std::to_string(row_valid.size()) + " entries for " +
           std::to_string(visibility.height) + " rows";
  }
  return std::nullopt;
}

namespace {

constexpr double kExactLookup = 0.02;  // shader_interface.h's kClientWarpExactLookup

// What one source says about one pixel (warp.comp's Lookup).
struct SourceLookup {
  WarpStatus status = WarpStatus::kNoData;
  uint32_t agree = 0;
  uint32_t value = 0;
  bool exact = false;
  glm::dvec2 pixel{0.0};
  double margin = std::numeric_limits<double>::infinity();
  uint32_t refined = shader::kClientSoftRefineNoneAll;  // settings.soft_refine: soft_refine's shares
};

// The depth test's plane check for old pixel (a, b) of `src` (its traced depth must be there): whether the old
// surface there lies within `tolerance` of this pixel's tangent plane (p_old, n_old in the old eye's space);
// lowers `margin` by how close the distance is to the tolerance. False too where the old pixel saw no surface.
bool on_tangent_plane(const WarpInput& input, const WarpSource& src, int a, int b, const glm::dvec3& p_old,
                      const glm::dvec3& n_old, double depth_old, double tolerance, double& margin) {
  // Texel (a, b) / k of the traced depth, along the ray through its centre (bilinear_warp.h's warp_depth_point).
  const int k = static_cast<int>(input.settings.depth_scale);
  const int ta = a / k, tb = b / k;
  const size_t depth_width = (size_t{src.traced.extent.width} + k - 1) / k;
  const double ds = src.traced_depth[static_cast<size_t>(tb) * depth_width + static_cast<size_t>(ta)];
  if (!(ds > 0.0)) return false;
  const glm::dvec3 q = (input.near_plane / ds) * src.traced.eye_ray((ta + 0.5) * k, (tb + 0.5) * k);
  const double dist = std::abs(glm::dot(n_old, q - p_old));
  margin = std::min(margin, std::abs(dist - tolerance) / depth_old * 200.0);
  return dist <= tolerance;
}

// The edge band (warp_edges.hpp), scanned here for each used sample: the bits of `bits` on which the arrived old
// pixels within `band` (Chebyshev) of a used sample (first + (k & 1, k >> 1)) do not all agree.
uint32_t band_disagreement(const WarpSource& src, uint32_t bits, int i0, int j0, uint32_t used, int band) {
  const Extent old = src.traced.extent;
  uint32_t out = 0;
  for (int k = 0; k < 4; ++k) {
    if (((used >> k) & 1u) == 0) continue;
    uint32_t and_m = 0xFFFFFFFFu, or_m = 0u;
    for (int b = j0 + (k >> 1) - band; b <= j0 + (k >> 1) + band; ++b) {
      if (b < 0 || b >= static_cast<int>(old.height)) continue;
      if (!src.row_valid.empty() && src.row_valid[static_cast<size_t>(b)] == 0) continue;
      for (int a = i0 + (k & 1) - band; a <= i0 + (k & 1) + band; ++a) {
        if (a < 0 || a >= static_cast<int>(old.width)) continue;
        const uint32_t m = src.visibility->get(static_cast<uint32_t>(a), static_cast<uint32_t>(b));
        and_m &= m;
        or_m |= m;
      }
    }
    out |= (and_m ^ or_m) & bits;
  }
  return out;
}

// edge_lights: soft_edge_light_mask of the input's lights (the soft fields an edge sends to the shadow maps).
// shares: the source's band shares (soft_band_table of refine_bits, soft_refine_bits of the layout) when the warp
// refines soft shares.
SourceLookup look_up(const WarpInput& input, const VisibilityLayout& layout, uint32_t edge_lights,
                     const WarpSource& src, const SoftBandTable* shares, uint32_t refine_bits,
                     const glm::dvec3& p_world, const glm::dvec3& n_world) {
  SourceLookup r;
  if (src.visibility == nullptr) return r;
  const Reprojection rep = reproject(src.traced, p_world, input.min_depth);
  // A depth within 1e-6 m of the threshold may be decided either way in float.
  r.margin = std::abs(rep.depth - input.min_depth) * 1e6;
  if (rep.status == Reprojection::Status::kBehind) {
    r.status = WarpStatus::kBehind;
    return r;
  }
  r.pixel = rep.pixel;
  r.margin = std::min(r.margin, lookup_margin(rep.pixel, src.traced.extent));
  if (rep.status == Reprojection::Status::kOutside) {
    r.status = WarpStatus::kOutside;
    return r;
  }
  const WarpSettings& set = input.settings;
  const Extent old = src.traced.extent;
  const bool depth_test = set.depth_test && !src.traced_depth.empty();
  const glm::dmat3 r_old_t = glm::transpose(eye_to_world_rotation(src.traced));
  const glm::dvec3 p_old = r_old_t * (p_world - src.traced.T_world_eye.position);
  const glm::dvec3 n_old = r_old_t * n_world;
  const double depth_old = -p_old.z;
  const double tolerance = set.plane_tolerance_rel * depth_old + set.plane_tolerance_abs;
  const double bx = set.bilinear ? rep.pixel.x - 0.5 : rep.pixel.x;
  const double by = set.bilinear ? rep.pixel.y - 0.5 : rep.pixel.y;
  if (set.bilinear) r.margin = std::min(r.margin, std::min(boundary_distance(bx), boundary_distance(by)));
  const int i0 = static_cast<int>(std::floor(bx));
  const int j0 = static_cast<int>(std::floor(by));
  const double fx = bx - i0, fy = by - j0;
  const int n = set.bilinear ? 4 : 1;
  std::array<uint32_t, 4> masks{};
  std::array<double, 4> weights{};
  uint32_t and_m = 0xFFFFFFFFu, or_m = 0u, rows = 0, used = 0, arrived = 0;
  // Bilinear: a lookup at an old pixel centre (sample k_exact) takes that pixel's bit as exact when used;
  // traced from the display eye's own position it is this pixel's ray and skips the depth test.
  const int k_exact = (fx < 0.5 ? 0 : 1) + 2 * (fy < 0.5 ? 0 : 1);
  const double dx = std::min(fx, 1.0 - fx), dy = std::min(fy, 1.0 - fy);
  const bool centred = set.bilinear && dx <= kExactLookup && dy <= kExactLookup;
  const bool same_ray = centred && same_eye(input.display, src.traced);
  if (set.bilinear) {
    r.margin = std::min(r.margin, std::min(std::abs(dx - kExactLookup), std::abs(dy - kExactLookup)));
    r.margin = std::min(r.margin, std::min(std::abs(fx - 0.5), std::abs(fy - 0.5)));
  }
  for (int k = 0; k < n; ++k) {
    const int a = i0 + (k & 1);
    const int b = j0 + (k >> 1);
    weights[k] = set.bilinear ? ((k & 1) ? fx : 1.0 - fx) * ((k >> 1) ? fy : 1.0 - fy) : 1.0;
    if (a < 0 || b < 0 || a >= static_cast<int>(old.width) || b >= static_cast<int>(old.height)) continue;
    if (!src.row_valid.empty() && src.row_valid[static_cast<size_t>(b)] == 0) continue;
    ++rows;
    arrived |= 1u << k;
    if (depth_test && !(same_ray && k == k_exact) &&
        !on_tangent_plane(input, src, a, b, p_old, n_old, depth_old, tolerance, r.margin)) {
      continue;
    }
    const uint32_t m = src.visibility->get(static_cast<uint32_t>(a), static_cast<uint32_t>(b));
    masks[k] = m;
    used |= 1u << k;
    and_m &= m;
    or_m |= m;
  }
  if (rows == 0) {
    r.status = WarpStatus::kMissingRow;
    return r;
  }
  if (used == 0) {
    r.status = WarpStatus::kDisoccluded;
    return r;
  }
  r.status = WarpStatus::kKnown;
  // Refined soft shares (warp.comp's look_up): where every 2x2 sample that arrived was used.
  const bool refine = shares != nullptr && set.bilinear && used == arrived;
  std::array<uint32_t, 4> sample_shares{};
  sample_shares.fill(shader::kClientSoftRefineNoneAll);
  if (refine) {
    for (int k = 0; k < n; ++k) {
      if (((used >> k) & 1u) == 0) continue;
      sample_shares[k] = soft_band_shares_at(*shares, layout, static_cast<uint32_t>(i0 + (k & 1)),
                                             static_cast<uint32_t>(j0 + (k >> 1)), masks[k]);
    }
  }
  if (centred && ((used >> k_exact) & 1u)) {
    r.exact = true;
    r.agree = 0xFFFFFFFFu;
    r.value = masks[k_exact];
    if (refine) r.refined = soft_blend(layout, masks, sample_shares, used, fx, fy, r.value, k_exact, refine_bits);
    return r;
  }
  r.agree = ~(and_m ^ or_m);
  r.value = and_m;
  uint32_t open = or_m & ~and_m;
  if (open != 0) {
    double total = 0.0;
    for (int k = 0; k < n; ++k) total += (used >> k) & 1u ? weights[k] : 0.0;
    for (uint32_t bit = 0; bit < 32; ++bit) {
      if (((open >> bit) & 1u) == 0) continue;
      double set_weight = 0.0;
      for (int k = 0; k < n; ++k) {
        if (((used >> k) & 1u) && ((masks[k] >> bit) & 1u)) set_weight += weights[k];
      }
      r.margin = std::min(r.margin, std::abs(2.0 * set_weight - total));
      if (2.0 * set_weight >= total) r.value |= 1u << bit;
    }
  }
  // Soft fields the samples disagree on: the bilinear blend of their levels, quantized, agreed
  // (bilinear_warp.h's warp_vote_fields).
  if (layout.any_soft()) {
    double total = 0.0;
    for (int k = 0; k < n; ++k) total += (used >> k) & 1u ? weights[k] : 0.0;
    for (uint32_t i = 0; i < layout.light_count; ++i) {
      const uint32_t field = ((1u << layout.bits[i]) - 1u) << layout.offset[i];
      if (!layout.is_soft(i) || (~r.agree & field) == 0) continue;
      double blend = 0.0;
      float lowest = 1.0f, highest = 0.0f;
      for (int k = 0; k < n; ++k) {
        if (((used >> k) & 1u) == 0) continue;
        const float f = layout.visibility(masks[k], i);
        blend += weights[k] * static_cast<double>(f);
        lowest = std::min(lowest, f);
        highest = std::max(highest, f);
      }
      blend /= total;
      // The level flips where blend x 7 crosses a half: a lookup moving by one old pixel moves it by at most 7.
      const double scaled = blend * (kDefaultSoftLevels - 1);
      r.margin = std::min(r.margin, std::abs(scaled - std::floor(scaled) - 0.5) / (kDefaultSoftLevels - 1));
      r.value = layout.with_visibility(r.value, i, static_cast<float>(blend));
      // A sun's levels spanning more than kClientWarpSoftEdgeSpread: an edge, undecided (exact integers: no margin).
      const auto spread = static_cast<uint32_t>(std::lround((highest - lowest) * (kDefaultSoftLevels - 1)));
      if (((edge_lights >> i) & 1u) == 0 || spread <= shader::kClientWarpSoftEdgeSpread) r.agree |= field;
    }
  }
  if (set.bilinear && set.edge_band > 0) {
    r.agree &= ~band_disagreement(src, hard_field_bits(layout), i0, j0, used, static_cast<int>(set.edge_band));
  }
  if (refine) r.refined = soft_blend(layout, masks, sample_shares, used, fx, fy, r.value, -1, refine_bits);
  return r;
}

// The neighbour fill (warp.comp's look_up_neighbours) for source `src` and the surface point p.
SourceLookup look_up_neighbours(const WarpInput& input, const WarpSource& src, const glm::dvec3& p_world,
                                const glm::dvec3& n_world) {
  SourceLookup r;
  r.status = WarpStatus::kDisoccluded;
  const Reprojection rep = reproject(src.traced, p_world, input.min_depth);
  r.margin = std::abs(rep.depth - input.min_depth) * 1e6;
  if (rep.status == Reprojection::Status::kBehind) return r;
  r.pixel = rep.pixel;
  const Extent old = src.traced.extent;
  const WarpSettings& set = input.settings;
  const glm::dmat3 r_old_t = glm::transpose(eye_to_world_rotation(src.traced));
  const glm::dvec3 p_old = r_old_t * (p_world - src.traced.T_world_eye.position);
  const glm::dvec3 n_old = r_old_t * n_world;
  const double depth_old = -p_old.z;
  const double tolerance = set.plane_tolerance_rel * depth_old + set.plane_tolerance_abs;
  const double px = std::clamp(rep.pixel.x, -64.0, old.width + 64.0);
  const double py = std::clamp(rep.pixel.y, -64.0, old.height + 64.0);
  r.margin = std::min(r.margin, std::min(boundary_distance(px), boundary_distance(py)));  // the window's place
  const int ci = static_cast<int>(std::floor(px));
  const int cj = static_cast<int>(std::floor(py));
  std::vector<double> passing;  // squared distances of the candidates that pass
  double best = std::numeric_limits<double>::infinity();
  int best_a = -1, best_b = -1;
  for (int b = cj - kNeighbourRadius; b <= cj + kNeighbourRadius; ++b) {
    if (b < 0 || b >= static_cast<int>(old.height)) continue;
    if (!src.row_valid.empty() && src.row_valid[static_cast<size_t>(b)] == 0) continue;
    for (int a = ci - kNeighbourRadius; a <= ci + kNeighbourRadius; ++a) {
      if (a < 0 || a >= static_cast<int>(old.width)) continue;
      if (!on_tangent_plane(input, src, a, b, p_old, n_old, depth_old, tolerance, r.margin)) continue;
      const double ex = a + 0.5 - rep.pixel.x, ey = b + 0.5 - rep.pixel.y;
      const double d2 = ex * ex + ey * ey;
      passing.push_back(d2);
      if (d2 < best) {
        best = d2;
        best_a = a;
        best_b = b;
      }
    }
  }
  if (best_a < 0) return r;
  // The choice flips when another candidate's distance comes within float rounding of the best one's.
  bool seen_best = false;
  for (double d2 : passing) {
    if (d2 == best && !seen_best) {
      seen_best = true;
      continue;
    }
    r.margin = std::min(r.margin, (d2 - best) / (4.0 * (kNeighbourRadius + 1)));
  }
  r.status = WarpStatus::kKnown;
  r.agree = 0xFFFFFFFFu;
  r.value = src.visibility->get(static_cast<uint32_t>(best_a), static_cast<uint32_t>(best_b));
  return r;
}

}  // namespace

WarpResult warp_reference(const WarpInput& input) {
  if (auto err = validate_camera(input.display)) throw std::invalid_argument("display camera: " + *err);
  const Extent extent = input.display.extent;
  const size_t n = size_t{extent.width} * extent.height;
  if (input.depth.size() != n) {
    throw std::invalid_argument("warp reference: depth has " + std::to_string(input.depth.size()) +
                                " values for a " + std::to_string(extent.width) + "x" +
                                std::to_string(extent.height) + " camera");
  }
  const WarpSettings& set = input.settings;
  const bool needs_normals = set.depth_test || set.shadow_fill || set.shadow_edges || set.shadow_first;
  if (needs_normals && input.normals.size() != n) {
    throw std::invalid_argument("warp reference: the depth test and shadow lookups need one normal per pixel");
  }
  if (set.uses_shadow_maps() && input.shadow == nullptr) {
    throw std::invalid_argument("warp reference: shadow settings without shadow maps");
  }
  if (set.edge_band > kMaxEdgeBand) throw std::invalid_argument("warp reference: edge band above kMaxEdgeBand");
  std::array<WarpSource, 3> sources = input.sources;
  if (!set.other_eye) sources[1].visibility = nullptr;
  if (!set.older_buffer) sources[2].visibility = nullptr;
  for (size_t s = 0; s < sources.size(); ++s) {
    const WarpSource& src = sources[s];
    if (src.visibility == nullptr) continue;
    if (auto err = validate_visibility_input(src.traced, *src.visibility, src.row_valid)) {
      throw std::invalid_argument("warp reference: source " + std::to_string(s) + ": " + *err);
    }
    const Extent depth_extent = depth_camera(src.traced, set.depth_scale).extent;
    if (!src.traced_depth.empty() && src.traced_depth.size() != size_t{depth_extent.width} * depth_extent.height) {
      throw std::invalid_argument("warp reference: source " + std::to_string(s) + ": traced depth size");
    }
  }
  const uint32_t unknown = unknown_mask(sources[0].visibility, input.lights);
  // The fields the bilinear vote blends: once per warp, not per lookup.
  const std::span<const SceneLight> lights = input.lights.first(std::min<size_t>(input.lights.size(), kMaxLights));
  const VisibilityLayout layout = layout_for_lights(lights);
  const uint32_t edge_lights = soft_edge_light_mask(lights);
  // Refined soft shares: each source's band shares, once per warp (the GPU passes: once per upload).
  const uint32_t refine_bits = set.soft_refine && set.bilinear ? soft_refine_bits(layout, edge_lights) : 0u;
  std::array<SoftBandTable, 3> tables;
  std::array<const SoftBandTable*, 3> shares{};
  for (size_t s = 0; s < sources.size(); ++s) {
    if (refine_bits != 0 && sources[s].visibility != nullptr) {
      const VisibilityBuffer& buffer = *sources[s].visibility;
      tables[s] = soft_band_table(layout, buffer, sources[s].row_valid, refine_bits, soft_band_radius(buffer.width));
      shares[s] = &tables[s];
    }
  }
  WarpResult out;
  out.extent = extent;
  out.masks.assign(n, unknown);
  out.status.assign(n, WarpStatus::kKnown);
  out.fill.assign(n, WarpFill::kNone);
  out.lookup.assign(n, glm::dvec2(0.0));
  out.margin.assign(n, std::numeric_limits<double>::infinity());
  out.soft.assign(n, shader::kClientSoftRefineNoneAll);

  for (uint32_t y = 0; y < extent.height; ++y) {
    for (uint32_t x = 0; x < extent.width; ++x) {
      const size_t i = size_t{y} * extent.width + x;
      const double d = input.depth[i];
      if (!(d > 0.0)) {
        out.status[i] = WarpStatus::kBackground;
        ++out.counts.by_status[static_cast<size_t>(WarpStatus::kBackground)];
        continue;
      }
      const glm::dvec3 p = world_point_from_depth(input.display, input.near_plane, x + 0.5, y + 0.5, d);
      const glm::dvec3 nrm = needs_normals ? glm::normalize(glm::dvec3(input.normals[i])) : glm::dvec3(0.0);
      const SourceLookup own = look_up(input, layout, edge_lights, sources[0], shares[0], refine_bits, p, nrm);
      double margin = own.margin;
      out.status[i] = own.status;
      out.lookup[i] = own.pixel;
      SourceLookup chosen = own;
      uint32_t chosen_source = 0;
      if (own.status != WarpStatus::kKnown && sources[1].visibility != nullptr) {
        const SourceLookup other = look_up(input, layout, edge_lights, sources[1], shares[1], refine_bits, p, nrm);
        margin = std::min(margin, other.margin);
        if (other.status == WarpStatus::kKnown) {
          chosen = other;
          chosen_source = 1;
          out.fill[i] = WarpFill::kOtherEye;
        }
      }
      if (own.status != WarpStatus::kKnown && out.fill[i] == WarpFill::kNone && sources[2].visibility != nullptr) {
        const SourceLookup older = look_up(input, layout, edge_lights, sources[2], shares[2], refine_bits, p, nrm);
        margin = std::min(margin, older.margin);
        if (older.status == WarpStatus::kKnown) {
          chosen = older;
          chosen_source = 2;
          out.fill[i] = WarpFill::kOlder;
        }
      }
      const bool neighbour_status = own.status == WarpStatus::kOutside || own.status == WarpStatus::kMissingRow ||
                                    own.status == WarpStatus::kDisoccluded;
      if (out.fill[i] == WarpFill::kNone && set.neighbour_fill && set.depth_test && neighbour_status &&
          !sources[0].traced_depth.empty()) {
        const SourceLookup neighbour = look_up_neighbours(input, sources[0], p, nrm);
        margin = std::min(margin, neighbour.margin);
        if (neighbour.status == WarpStatus::kKnown) {
          chosen = neighbour;
          out.fill[i] = WarpFill::kNeighbour;
        }
      }
      const bool have = own.status == WarpStatus::kKnown || out.fill[i] != WarpFill::kNone;
      // Motion: the chosen source's bits that something moved since its scene time may have changed.
      uint32_t moved = 0;
      if (have && set.motion && input.motion != nullptr) {
        double motion_margin = 0.0;
        moved = motion_unknown_bits(*input.motion, chosen_source, p - input.display.T_world_eye.position,
                                    layout.light_count, unknown, &motion_margin);
        margin = std::min(margin, motion_margin);
      }
      const uint32_t undecided = have ? ~chosen.agree & unknown : 0u;
      const uint32_t to_shadow = set.uses_shadow_maps() ? moved : 0u;
      const bool need_shadow = have ? (set.shadow_first && !chosen.exact) || (set.shadow_edges && undecided != 0) ||
                                          to_shadow != 0
                                    : set.shadow_fill;
      ShadowDecision shadow;
      if (need_shadow) {
        const double depth = input.near_plane / d;
        const double pixel_world = depth * input.display.tangents.width() / input.display.extent.width;
        shadow = shadow_mask_reference(*input.shadow, input.lights, p, nrm, pixel_world);
        margin = std::min(margin, shadow.margin);
      }
      if (have) {
        const uint32_t from_shadow = (set.shadow_first && !chosen.exact ? shadow.confident : 0u) |
                                     (set.shadow_edges ? undecided : 0u) | to_shadow;
        out.masks[i] = (chosen.value & ~from_shadow) | (shadow.mask & from_shadow);
        out.soft[i] = soft_refine_drop(layout, chosen.refined, from_shadow);
        if (moved != 0) ++out.counts.motion_unknown;
        if (set.shadow_edges && undecided != 0) ++out.counts.edges_shadow_map;
        if ((from_shadow & ~undecided & ~to_shadow & (chosen.value ^ shadow.mask) & unknown) != 0)
          ++out.counts.shadow_overrides;
      } else if (set.shadow_fill) {
        out.masks[i] = shadow.mask;
        out.fill[i] = WarpFill::kShadowMap;
      }
      out.margin[i] = margin;
      ++out.counts.by_status[static_cast<size_t>(out.status[i])];
      if (out.fill[i] == WarpFill::kOtherEye) ++out.counts.filled_other_eye;
      if (out.fill[i] == WarpFill::kShadowMap) ++out.counts.filled_shadow_map;
      if (out.fill[i] == WarpFill::kOlder) ++out.counts.filled_older;
      if (out.fill[i] == WarpFill::kNeighbour) ++out.counts.filled_neighbour;
    }
  }
  return out;
}

}  // namespace dhr::render
