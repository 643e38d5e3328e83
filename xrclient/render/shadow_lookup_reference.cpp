// The CPU side of the client's shadow-map lookup (render/shadow_maps.hpp): where a direction falls on a light's cube
// (cube_lookup, the C++ twin of shaders/client/cube_face.h) and the warp's lookup on a read-back atlas
// (shadow_mask_reference, the twin of shaders/client/shadow_lookup.h), for the warp's CPU reference and the tests.
#include <algorithm>
#include <cmath>
#include <limits>

#include "render/light_layout.hpp"
#include "render/pcss_reference.hpp"
#include "render/shadow_maps.hpp"
#include "render/sun_map.hpp"
#include "scene/lighting.hpp"

namespace dhr::render {
namespace {

double boundary_distance(double v) { return std::abs(v - std::round(v)); }

}  // namespace

double cube_face_distance(const glm::dvec3& v) {
  return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z)));
}

CubeLookup cube_lookup(const glm::dvec3& v, uint32_t size) {
  const glm::dvec3 a = glm::abs(v);
  CubeLookup c;
  double x = 0.0, y = 0.0, tie = 0.0;
  if (a.x >= a.y && a.x >= a.z) {
    c.distance = a.x;
    c.face = v.x >= 0.0 ? 0u : 1u;
    x = v.x >= 0.0 ? v.z : -v.z;
    y = v.y;
    tie = std::min(a.x - a.y, a.x - a.z);
  } else if (a.y >= a.z) {
    c.distance = a.y;
    c.face = v.y >= 0.0 ? 2u : 3u;
    x = v.x;
    y = v.y >= 0.0 ? v.z : -v.z;
    tie = std::min(a.y - a.x, a.y - a.z);
  } else {
    c.distance = a.z;
    c.face = v.z >= 0.0 ? 4u : 5u;
    x = v.z >= 0.0 ? -v.x : v.x;
    y = v.y;
    tie = std::min(a.z - a.x, a.z - a.y);
  }
  const double s = size;
  c.position = glm::dvec2((x / c.distance + 1.0) * 0.5 * s, (1.0 - y / c.distance) * 0.5 * s);
  const int last = static_cast<int>(size) - 1;
  c.texel = glm::ivec2(std::clamp(static_cast<int>(std::floor(c.position.x)), 0, last),
                       std::clamp(static_cast<int>(std::floor(c.position.y)), 0, last));
  // Face ties in texels (a relative difference of the two largest components maps to about size/2 texels).
  c.margin = tie / c.distance * 0.5 * s;
  for (double p : {c.position.x, c.position.y}) {
    if (p > 0.0 && p < s) c.margin = std::min(c.margin, boundary_distance(p));
  }
  return c;
}

ShadowDecision shadow_mask_reference(const ShadowReference& maps, std::span<const SceneLight> lights,
                                     const glm::dvec3& p, const glm::dvec3& n, double pixel_world) {
  ShadowDecision out;
  out.margin = std::numeric_limits<double>::infinity();
  const uint32_t size = maps.face_size;
  const size_t atlas_width = size_t{6} * size;
  const VisibilityLayout layout = layout_for_lights(lights.first(std::min<size_t>(lights.size(), kMaxLights)));
  for (uint32_t i = 0; i < layout.light_count; ++i) {
    const SceneLight& light = lights[i];
    const uint32_t field = ((1u << layout.bits[i]) - 1u) << layout.offset[i];
    // light_test in double, with the margins of its decisions.
    glm::dvec3 l;
    double dist = std::numeric_limits<double>::infinity();
    if (light.type == SceneLight::Type::kDirectional) {
      l = -glm::dvec3(light.direction);
    } else {
      const glm::dvec3 d = glm::dvec3(light.position) - p;
      dist = glm::length(d);
      if (!(dist > 0.0)) {
        out.confident |= field;
        continue;
      }
      l = d / dist;
      const double range = light.range;
      if (range > 0.0) {
        out.margin = std::min(out.margin, std::abs(dist - range) / range * 1e3);
        if (!(dist < range)) {
          out.confident |= field;
          continue;
        }
      }
      if (light.type == SceneLight::Type::kSpot) {
        const double cd = glm::dot(-l, glm::dvec3(light.direction));
        const double outer = std::cos(static_cast<double>(light.outer_cone));
        out.margin = std::min(out.margin, std::abs(cd - outer) * 1e3);
        if (!(cd > outer)) {
          out.confident |= field;
          continue;
        }
      }
      // Rect and disk lights emit from one side only (light_eval's light_test).
      if (light.type == SceneLight::Type::kRect || light.type == SceneLight::Type::kDisk) {
        const double cd = glm::dot(-l, glm::dvec3(light.direction));
        out.margin = std::min(out.margin, std::abs(cd) * 1e3);
        if (!(cd > 0.0)) {
          out.confident |= field;
          continue;
        }
      }
    }
    const double nl = glm::dot(n, l);
    out.margin = std::min(out.margin, std::abs(nl) * 1e3);
    if (!(nl > 0.0)) {
      out.confident |= field;
      continue;
    }
    const ShadowTile& tile = maps.tiles.at(i);
    if (!tile.row) {
      out.mask = layout.with_visibility(out.mask, i, 1.0f);
      continue;
    }
    const glm::dvec3 v0 = p - tile.position;
    const double texel = tile.sun ? 2.0 * tile.sun->half_extent / size : 2.0 * cube_face_distance(v0) / size;
    const glm::dvec3 v = v0 + (maps.settings.normal_offset * texel) * n;
    const CubeLookup c = tile.sun ? sun_lookup(*tile.sun, v, size) : cube_lookup(v, size);
    out.margin = std::min(out.margin, c.margin);
    const double tan_nl = std::min(std::sqrt(std::max(1.0 - nl * nl, 0.0)) / nl, 10.0);
    if (layout.is_soft(i)) {
      // PCSS (pcss_reference.hpp); confident where every filter tap agrees. Its taps' flips are not in `margin`:
      // a tap within rounding of its threshold moves the level by one step (the tests count such pixels).
      // Texels per unit of the similar-triangles term (pcss.h): cube R / d x size / 2, sun tan / texel.
      const double scale = tile.sun ? pcss_light_radius(light) / texel : pcss_light_radius(light) / c.distance * 0.5 * size;
      const double fraction = pcss_fraction_reference(maps, tile, c, scale,
                                                      maps.settings.bias_rel * c.distance + maps.settings.bias_abs,
                                                      texel * tan_nl);
      out.mask = layout.with_visibility(out.mask, i, static_cast<float>(fraction));
      if (fraction == 0.0 || fraction == 1.0) out.confident |= field;
      continue;
    }
    const double bias =
        maps.settings.bias_rel * c.distance + maps.settings.bias_abs + maps.settings.bias_slope * texel * tan_nl;
    // Whether texel t (clamped to the face) holds nothing nearer than `threshold`.
    auto texel_lit = [&](glm::ivec2 t, double threshold) {
      const int last = static_cast<int>(size) - 1;
      t = glm::clamp(t, glm::ivec2(0), glm::ivec2(last));
      const size_t index = (size_t{*tile.row} * size + static_cast<size_t>(t.y)) * atlas_width +
                           size_t{c.face} * size + static_cast<size_t>(t.x);
      const double stored = maps.atlas[index];
      const double occluder = stored > 0.0 ? (tile.sun ? (1.0 - stored) * tile.sun->depth_range
                                                       : maps.settings.near_plane / stored)
                                           : 3.0e38;
      out.margin = std::min(out.margin, std::abs(occluder - threshold) / c.distance * 1e3);
      return occluder >= threshold;
    };
    const double threshold = c.distance - bias;
    const bool lit = texel_lit(c.texel, threshold);
    if (lit) out.mask |= field;
    bool alike = true;
    out.margin = std::min(out.margin, std::abs(texel - pixel_world) / pixel_world * 1e3);
    if (texel > pixel_world) {
      const glm::ivec2 t0(static_cast<int>(std::floor(c.position.x - 0.5)),
                          static_cast<int>(std::floor(c.position.y - 0.5)));
      out.margin = std::min(out.margin, std::min(boundary_distance(c.position.x - 0.5),
                                                 boundary_distance(c.position.y - 0.5)));
      for (int k = 0; k < 4; ++k) alike = alike && texel_lit(t0 + glm::ivec2(k & 1, k >> 1), threshold) == lit;
    }
    if (alike) out.confident |= field;
  }
  return out;
}

}  // namespace dhr::render
