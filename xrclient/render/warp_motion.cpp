#include "render/warp_motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dhr::render {

namespace {

// The largest distance of an emitting point from the light's centre (every shadow ray towards the light passes
// within it of the ray towards the centre), or for a sun the tangent of its angular radius.
double light_growth(const SceneLight& light) {
  switch (light.type) {
    case SceneLight::Type::kDirectional: return std::tan(0.5 * static_cast<double>(light.angle));
    case SceneLight::Type::kRect:
      return 0.5 * std::hypot(static_cast<double>(light.width), static_cast<double>(light.height));
    case SceneLight::Type::kDisk: return 0.5 * static_cast<double>(light.width);
    default: return static_cast<double>(light.radius);
  }
}

uint32_t field_bits(const VisibilityLayout& layout, uint32_t light) {
  return ((1u << layout.bits[light]) - 1u) << layout.offset[light];
}

WorldBox box_of(const shader::ClientMotionSource& src, uint32_t b) {
  WorldBox box;
  for (int k = 0; k < 3; ++k) {
    box.min[k] = src.box_min[3 * b + k];
    box.max[k] = src.box_max[3 * b + k];
  }
  return box;
}

// How far p is from the box's surface (inside or out), metres.
double surface_distance(const WorldBox& box, const glm::dvec3& p) {
  double inside = std::numeric_limits<double>::infinity(), outside = 0.0;
  for (int k = 0; k < 3; ++k) {
    inside = std::min({inside, p[k] - box.min[k], box.max[k] - p[k]});
    outside = std::max({outside, box.min[k] - p[k], p[k] - box.max[k]});
  }
  return inside > 0.0 ? inside : outside;
}

}  // namespace

void make_warp_motion(const WarpMotionInput& input, std::vector<WorldBox>& scratch, shader::ClientWarpMotion& out) {
  out = shader::ClientWarpMotion{};
  if (input.motion == nullptr || !input.motion->moves()) return;
  out.enabled = 1u;
  out.far_distance = static_cast<float>(input.far_distance);
  out.receiver_margin = static_cast<float>(kMotionReceiverMargin);
  const uint32_t lights = std::min<uint32_t>(input.layout.light_count, static_cast<uint32_t>(input.lights.size()));
  for (uint32_t l = 0; l < lights && l < 32; ++l) {
    const SceneLight& light = input.lights[l];
    shader::ClientMotionLight& ml = out.light[l];
    const bool directional = light.type == SceneLight::Type::kDirectional;
    const glm::dvec3 to = directional ? -glm::dvec3(light.direction) : glm::dvec3(light.position) - input.eye;
    for (int k = 0; k < 3; ++k) ml.to_light[k] = static_cast<float>(to[k]);
    ml.growth = static_cast<float>(light_growth(light));
    ml.field = field_bits(input.layout, l);
    ml.directional = directional ? 1u : 0u;
  }
  for (uint32_t s = 0; s < 3; ++s) {
    if (!input.source_times[s]) continue;
    const double t = *input.source_times[s];
    shader::ClientMotionSource& src = out.source[s];
    const uint32_t moved = input.motion->moved_lights(t, input.display_time, input.overrides);
    for (uint32_t l = 0; l < lights && l < 32; ++l)
      if ((moved >> l) & 1u) src.moved_bits |= field_bits(input.layout, l);
    input.motion->moved_boxes(t, input.display_time, scratch, input.overrides);
    if (scratch.size() > shader::kClientMaxMotionBoxes) {
      src.box_count = shader::kClientMaxMotionBoxes + 1;
      continue;
    }
    src.box_count = static_cast<uint32_t>(scratch.size());
    for (uint32_t b = 0; b < src.box_count; ++b) {
      for (int k = 0; k < 3; ++k) {
        src.box_min[3 * b + k] = static_cast<float>(scratch[b].min[k] - input.eye[k]);
        src.box_max[3 * b + k] = static_cast<float>(scratch[b].max[k] - input.eye[k]);
      }
    }
  }
}

uint32_t motion_unknown_bits(const shader::ClientWarpMotion& m, uint32_t s, const glm::dvec3& p, uint32_t light_count,
                             uint32_t unknown_mask, double* margin) {
  double closest = std::numeric_limits<double>::infinity();
  const auto done = [&](uint32_t bits) {
    if (margin != nullptr) *margin = closest;
    return bits & unknown_mask;
  };
  if (m.enabled == 0u) return done(0u);
  const shader::ClientMotionSource& src = m.source[s];
  uint32_t bits = src.moved_bits;
  if (src.box_count > shader::kClientMaxMotionBoxes) return done(unknown_mask);
  for (uint32_t b = 0; b < src.box_count; ++b) {
    const WorldBox box = grown(box_of(src, b), static_cast<double>(m.receiver_margin));
    closest = std::min(closest, surface_distance(box, p));
    if (box_contains(box, p)) return done(unknown_mask);
  }
  for (uint32_t l = 0; l < light_count && l < 32 && src.box_count > 0; ++l) {
    const shader::ClientMotionLight& ml = m.light[l];
    if ((bits & ml.field) == ml.field) continue;
    const glm::dvec3 to(ml.to_light[0], ml.to_light[1], ml.to_light[2]);
    const bool directional = ml.directional != 0u;
    const glm::dvec3 e = directional ? p + static_cast<double>(m.far_distance) * to : to;
    const double growth = static_cast<double>(ml.growth);
    const double grow = directional ? growth * static_cast<double>(m.far_distance) : growth;
    for (uint32_t b = 0; b < src.box_count; ++b) {
      const WorldBox box = grown(box_of(src, b), grow);
      // How far the slab test is from flipping (the tests keep pixels near a flip out of the GPU comparison).
      closest = std::min(closest, segment_box_gap(p, e, box));
      if (segment_hits_box(p, e, box)) {
        bits |= ml.field;
        break;
      }
    }
  }
  return done(bits);
}

}  // namespace dhr::render
