#include "render/light_layout.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "shaders/shader_interface.h"

namespace dhr::render {

static_assert(shader::kClientSoftBits == kSoftLevelBits, "the shaders' soft field width is the layout's");
static_assert(shader::kClientSoftLevels == kDefaultSoftLevels, "the shaders' soft levels are the layout's");

VisibilityLayout layout_for_lights(std::span<const SceneLight> lights) {
  if (lights.size() > kMaxLights) throw std::invalid_argument("visibility layout: more than 32 lights");
  std::array<bool, kMaxLights> soft{};
  for (size_t i = 0; i < lights.size(); ++i) soft[i] = lights[i].has_extent();
  return VisibilityLayout::for_lights(std::span<const bool>(soft.data(), lights.size()));
}

uint32_t soft_light_mask(const VisibilityLayout& layout) {
  uint32_t mask = 0, offset = 0;
  for (uint32_t i = 0; i < layout.light_count; ++i) {
    if (layout.offset[i] != offset) throw std::logic_error("visibility layout: fields are not in the lights' order");
    if (layout.is_soft(i)) mask |= 1u << i;
    offset += layout.bits[i];
  }
  return mask;
}

uint32_t soft_edge_light_mask(std::span<const SceneLight> lights) {
  uint32_t mask = 0;
  for (size_t i = 0; i < std::min<size_t>(lights.size(), kMaxLights); ++i) {
    if (lights[i].type == SceneLight::Type::kDirectional && lights[i].has_extent()) mask |= 1u << i;
  }
  return mask;
}

double pcss_light_radius(const SceneLight& light) {
  switch (light.type) {
    case SceneLight::Type::kPoint:
    case SceneLight::Type::kSpot:
      return static_cast<double>(light.radius);
    case SceneLight::Type::kRect:
      return std::sqrt(static_cast<double>(light.width) * static_cast<double>(light.height) / std::numbers::pi);
    case SceneLight::Type::kDisk:
      return 0.5 * static_cast<double>(light.width);
    case SceneLight::Type::kDirectional:
      return std::tan(0.5 * static_cast<double>(light.angle));
  }
  return 0.0;
}

}  // namespace dhr::render
