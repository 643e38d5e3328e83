// Lights: type names, the default rig, validation, and a light's extent (area, description). Reading lights from
// glTF is in scene_gltf_lights.cpp, spec strings in scene_light_spec.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>

#include "scene/scene.hpp"

namespace dhr {
namespace {

constexpr float kPi = 3.14159265358979f;

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool unit(const glm::vec3& v) { return std::abs(glm::length(v) - 1.0f) <= 1e-3f; }

// The extent fields a light of this type must leave at 0 (a sphere radius on a sun, a sun angle on a rect...).
std::optional<std::string> check_extent(const SceneLight& light) {
  const std::string& name = light.name;
  if (!std::isfinite(light.radius) || !std::isfinite(light.angle) || !std::isfinite(light.width) ||
      !std::isfinite(light.height) || !finite(light.tangent) || !finite(light.bitangent)) {
    return "light '" + name + "' has a non-finite extent";
  }
  if (light.radius < 0.0f || light.angle < 0.0f || light.width < 0.0f || light.height < 0.0f)
    return "light '" + name + "' has a negative extent";
  const bool sphere_ok = light.type == SceneLight::Type::kPoint || light.type == SceneLight::Type::kSpot;
  const bool area = light.type == SceneLight::Type::kRect || light.type == SceneLight::Type::kDisk;
  if (light.radius > 0.0f && !sphere_ok) return "light '" + name + "': only point and spot lights take a radius";
  if (light.angle > 0.0f && light.type != SceneLight::Type::kDirectional)
    return "light '" + name + "': only directional lights take an angle";
  if (!area && (light.width > 0.0f || light.height > 0.0f))
    return "light '" + name + "': only rect and disk lights take a width and height";
  if (light.radius > kMaxLightExtent || light.width > kMaxLightExtent || light.height > kMaxLightExtent) {
    return "light '" + name + "' is larger than " + std::to_string(static_cast<int>(kMaxLightExtent)) + " m";
  }
  if (light.angle > kMaxLightAngle) return "light '" + name + "' has an angle above 0.5 rad (29 degrees)";
  if (!area) return std::nullopt;
  if (!(light.width > 0.0f && light.height > 0.0f))
    return "area light '" + name + "' needs a positive width and height";
  if (light.type == SceneLight::Type::kDisk && light.width != light.height)
    return "disk light '" + name + "' needs width == height (its diameter)";
  if (!unit(light.tangent) || !unit(light.bitangent) || std::abs(glm::dot(light.tangent, light.direction)) > 1e-3f ||
      std::abs(glm::dot(light.bitangent, light.direction)) > 1e-3f ||
      std::abs(glm::dot(light.tangent, light.bitangent)) > 1e-3f) {
    return "area light '" + name + "' needs an orthonormal frame (tangent, bitangent, direction)";
  }
  return std::nullopt;
}

}  // namespace

const char* light_type_name(SceneLight::Type type) {
  switch (type) {
    case SceneLight::Type::kPoint:
      return "point";
    case SceneLight::Type::kSpot:
      return "spot";
    case SceneLight::Type::kDirectional:
      return "dir";
    case SceneLight::Type::kRect:
      return "rect";
    case SceneLight::Type::kDisk:
      return "disk";
  }
  return "?";
}

std::vector<SceneLight> make_default_light_rig(const SceneBounds& bounds) {
  // In double: a float box near the float limits (|coordinate| > ~1e19) overflows its size, and the
  // intensity (irradiance * d^2) overflows float for d > ~1e19 (issue 7). Results are clamped to float.
  glm::dvec3 lo(-1.0), hi(1.0);
  if (!bounds.empty()) {
    lo = glm::dvec3(bounds.min);
    hi = glm::dvec3(bounds.max);
  }
  const glm::dvec3 c = 0.5 * (lo + hi);
  // Keep a minimum extent so that flat or point-like scenes still get separated lights.
  const glm::dvec3 s = glm::max(hi - lo, glm::dvec3(0.5));
  auto point = [&](const char* name, const glm::dvec3& p, const glm::vec3& color, double irradiance_at_center) {
    constexpr double kFloatMax = std::numeric_limits<float>::max();
    SceneLight l;
    l.type = SceneLight::Type::kPoint;
    l.name = name;
    l.position = glm::vec3(glm::clamp(p, glm::dvec3(-kFloatMax), glm::dvec3(kFloatMax)));
    l.color = color;
    // E = I / d^2 at the centre of the box: choose I for the wanted irradiance there.
    const double d = glm::length(p - c);
    l.intensity = static_cast<float>(std::min(irradiance_at_center * std::max(d * d, 0.01), kFloatMax));
    l.is_default = true;
    return l;
  };
  std::vector<SceneLight> rig;
  // Key: high (85% of the height), front-right (+Z is the glTF front), inside the box so that
  // closed rooms with inward-facing walls are lit from inside.
  rig.push_back(point("default_key", glm::dvec3(c.x + 0.25 * s.x, lo.y + 0.85 * s.y, c.z + 0.3 * s.z),
                      glm::vec3(1.0f, 0.95f, 0.85f), 3.0));
  // Fill: lower, on the opposite side, cooler and dimmer.
  rig.push_back(point("default_fill", glm::dvec3(c.x - 0.3 * s.x, lo.y + 0.6 * s.y, c.z + 0.15 * s.z),
                      glm::vec3(0.8f, 0.87f, 1.0f), 1.0));
  SceneLight sun;
  sun.type = SceneLight::Type::kDirectional;
  sun.name = "default_sun";
  sun.direction = glm::normalize(glm::vec3(-0.35f, -1.0f, -0.25f));
  sun.color = glm::vec3(1.0f, 0.97f, 0.9f);
  sun.intensity = 1.5f;
  sun.is_default = true;
  rig.push_back(sun);
  return rig;
}

std::optional<std::string> validate_light(const SceneLight& light) {
  if (!finite(light.position) || !finite(light.direction) || !finite(light.color) || !std::isfinite(light.intensity) ||
      !std::isfinite(light.range) || !std::isfinite(light.inner_cone) || !std::isfinite(light.outer_cone)) {
    return "light '" + light.name + "' has non-finite values";
  }
  if (light.color.r < 0.0f || light.color.g < 0.0f || light.color.b < 0.0f)
    return "light '" + light.name + "' has a negative colour";
  if (light.intensity < 0.0f) return "light '" + light.name + "' has a negative intensity";
  if (light.range < 0.0f) return "light '" + light.name + "' has a negative range (0 means infinite)";
  if (light.type != SceneLight::Type::kPoint && std::abs(glm::length(light.direction) - 1.0f) > 1e-3f) {
    return "light '" + light.name + "' needs a unit direction";
  }
  if (light.type == SceneLight::Type::kSpot &&
      !(light.inner_cone >= 0.0f && light.inner_cone < light.outer_cone && light.outer_cone <= 0.5f * kPi + 1e-6f)) {
    return "spot light '" + light.name + "' needs 0 <= inner cone < outer cone <= 90 degrees";
  }
  return check_extent(light);
}

float SceneLight::area() const {
  if (type == Type::kRect) return width * height;
  if (type == Type::kDisk) return 0.25f * kPi * width * width;
  return 0.0f;
}

std::string describe_light_extent(const SceneLight& light) {
  char buf[96];
  const auto d = [](float x) { return static_cast<double>(x); };
  switch (light.type) {
    case SceneLight::Type::kRect:
      std::snprintf(buf, sizeof buf, "rect %.3g x %.3g m", d(light.width), d(light.height));
      return buf;
    case SceneLight::Type::kDisk:
      std::snprintf(buf, sizeof buf, "disk %.3g m", d(light.width));
      return buf;
    case SceneLight::Type::kDirectional:
      if (!(light.angle > 0.0f)) return "dir";
      std::snprintf(buf, sizeof buf, "dir, sun disk %.3g deg", d(light.angle * 180.0f / kPi));
      return buf;
    case SceneLight::Type::kPoint:
    case SceneLight::Type::kSpot:
      if (!(light.radius > 0.0f)) return light_type_name(light.type);
      std::snprintf(buf, sizeof buf, "%s, sphere r %.3g m", light_type_name(light.type), d(light.radius));
      return buf;
  }
  return "?";
}

std::optional<std::string> set_scene_lights(Scene& scene, std::vector<SceneLight> lights) {
  if (lights.size() > kMaxSceneLights) {
    return "too many lights: " + std::to_string(lights.size()) + " (at most " + std::to_string(kMaxSceneLights) + ")";
  }
  for (const SceneLight& l : lights) {
    if (auto problem = validate_light(l)) return problem;
  }
  scene.default_lights = !lights.empty();
  for (const SceneLight& l : lights) scene.default_lights = scene.default_lights && l.is_default;
  scene.lights = std::move(lights);
  return std::nullopt;
}

}  // namespace dhr
