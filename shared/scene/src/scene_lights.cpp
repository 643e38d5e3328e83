// Lights: KHR_lights_punctual placement, the default rig, and light spec strings.
#include <tiny_gltf.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <limits>

#include "scene/scene.hpp"
#include "scene_internal.hpp"

namespace dhr {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kDegrees = kPi / 180.0f;

glm::vec3 normalized_or(const glm::dvec3& v, const glm::vec3& fallback) {
  const double len = glm::length(v);
  if (!(len > 1e-12) || !std::isfinite(len)) return fallback;
  return glm::vec3(v / len);
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = s.find(sep, begin);
    parts.push_back(s.substr(begin, end == std::string_view::npos ? std::string_view::npos : end - begin));
    if (end == std::string_view::npos) break;
    begin = end + 1;
  }
  return parts;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Parses exactly `n` comma-separated finite numbers (locale-independent).
bool parse_numbers(std::string_view field, std::size_t n, float* out, const char* what, std::string* out_error) {
  const std::vector<std::string_view> parts = split(field, ',');
  if (parts.size() != n) {
    *out_error = std::string(what) + ": expected " + std::to_string(n) + " comma-separated numbers, got \"" +
                 std::string(field) + "\"";
    return false;
  }
  for (std::size_t i = 0; i < n; ++i) {
    std::string_view p = trim(parts[i]);
    if (!p.empty() && p.front() == '+') p.remove_prefix(1);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), v);
    if (p.empty() || ec != std::errc() || end != p.data() + p.size() || !std::isfinite(v) || std::abs(v) > 3.0e38) {
      *out_error = std::string(what) + ": \"" + std::string(parts[i]) + "\" is not a finite number";
      return false;
    }
    out[i] = static_cast<float>(v);
  }
  return true;
}

}  // namespace

namespace scene_detail {

SceneLight light_from_gltf(const tinygltf::Model& model, int index, const glm::dmat4& T_world_node) {
  const tinygltf::Light& src = model.lights[static_cast<std::size_t>(index)];
  SceneLight light;
  light.type = src.type == "spot"          ? SceneLight::Type::kSpot
               : src.type == "directional" ? SceneLight::Type::kDirectional
                                           : SceneLight::Type::kPoint;
  light.name = src.name.empty() ? format("light%d", index) : src.name;
  if (src.color.size() == 3) light.color = glm::vec3(src.color[0], src.color[1], src.color[2]);
  light.intensity = static_cast<float>(src.intensity);
  light.range = src.range > 0.0 ? static_cast<float>(src.range) : 0.0f;
  light.inner_cone = static_cast<float>(src.spot.innerConeAngle);
  light.outer_cone = static_cast<float>(src.spot.outerConeAngle);
  light.position = glm::vec3(T_world_node[3]);
  // Lights shine down their node's -Z axis.
  light.direction = normalized_or(glm::dmat3(T_world_node) * glm::dvec3(0.0, 0.0, -1.0), glm::vec3(0.0f, 0.0f, -1.0f));
  return light;
}

}  // namespace scene_detail

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
  return std::nullopt;
}

std::optional<SceneLight> parse_light_spec(std::string_view spec, std::string* out_error) {
  std::string ignored;
  std::string& error = out_error ? *out_error : ignored;
  const std::vector<std::string_view> f = split(trim(spec), ':');
  const std::string_view kind = f[0];
  SceneLight light;
  float v[3];
  auto fail = [&](const std::string& message) -> std::optional<SceneLight> {
    error = "light spec \"" + std::string(spec) + "\": " + message;
    return std::nullopt;
  };
  std::size_t next = 0;
  if (kind == "point") {
    if (f.size() != 4 && f.size() != 5) return fail("expected point:x,y,z:r,g,b:intensity[:range]");
    light.type = SceneLight::Type::kPoint;
    if (!parse_numbers(f[1], 3, v, "position", &error)) return fail(error);
    light.position = glm::vec3(v[0], v[1], v[2]);
    next = 2;
  } else if (kind == "spot") {
    if (f.size() != 6 && f.size() != 7)
      return fail("expected spot:x,y,z:dx,dy,dz:r,g,b:intensity:inner_deg,outer_deg[:range]");
    light.type = SceneLight::Type::kSpot;
    if (!parse_numbers(f[1], 3, v, "position", &error)) return fail(error);
    light.position = glm::vec3(v[0], v[1], v[2]);
    if (!parse_numbers(f[2], 3, v, "direction", &error)) return fail(error);
    light.direction = glm::vec3(v[0], v[1], v[2]);
    next = 3;
  } else if (kind == "dir" || kind == "directional") {
    if (f.size() != 4) return fail("expected dir:dx,dy,dz:r,g,b:intensity");
    light.type = SceneLight::Type::kDirectional;
    if (!parse_numbers(f[1], 3, v, "direction", &error)) return fail(error);
    light.direction = glm::vec3(v[0], v[1], v[2]);
    next = 2;
  } else {
    return fail("unknown light type \"" + std::string(kind) + "\" (use point, spot or dir)");
  }
  if (!parse_numbers(f[next], 3, v, "colour", &error)) return fail(error);
  light.color = glm::vec3(v[0], v[1], v[2]);
  if (!parse_numbers(f[next + 1], 1, v, "intensity", &error)) return fail(error);
  light.intensity = v[0];
  next += 2;
  if (light.type == SceneLight::Type::kSpot) {
    if (!parse_numbers(f[next], 2, v, "cone angles", &error)) return fail(error);
    light.inner_cone = v[0] * kDegrees;
    light.outer_cone = v[1] * kDegrees;
    ++next;
  }
  if (next < f.size()) {
    if (!parse_numbers(f[next], 1, v, "range", &error)) return fail(error);
    light.range = v[0];
  }
  if (light.type != SceneLight::Type::kPoint) {
    const float len = glm::length(light.direction);
    if (!(len > 1e-6f)) return fail("the direction must not be zero");
    light.direction /= len;
  }
  light.name = std::string(kind) + "_spec";
  if (auto problem = validate_light(light)) return fail(*problem);
  return light;
}

std::optional<std::vector<SceneLight>> parse_light_specs(std::string_view specs, std::string* out_error) {
  std::vector<SceneLight> lights;
  for (std::string_view part : split(specs, ';')) {
    if (trim(part).empty()) continue;
    auto light = parse_light_spec(part, out_error);
    if (!light) return std::nullopt;
    light->name += std::to_string(lights.size());  // "point_spec0", "dir_spec1", ...
    lights.push_back(std::move(*light));
  }
  if (lights.size() > kMaxSceneLights) {
    if (out_error)
      *out_error =
          "too many lights: " + std::to_string(lights.size()) + " (at most " + std::to_string(kMaxSceneLights) + ")";
    return std::nullopt;
  }
  return lights;
}

std::string format_light_spec(const SceneLight& l) {
  char buf[512];
  const auto d = [](float x) { return static_cast<double>(x); };
  switch (l.type) {
    case SceneLight::Type::kPoint:
      std::snprintf(buf, sizeof buf, "point:%.9g,%.9g,%.9g:%.9g,%.9g,%.9g:%.9g", d(l.position.x), d(l.position.y),
                    d(l.position.z), d(l.color.r), d(l.color.g), d(l.color.b), d(l.intensity));
      break;
    case SceneLight::Type::kSpot:
      std::snprintf(buf, sizeof buf, "spot:%.9g,%.9g,%.9g:%.9g,%.9g,%.9g:%.9g,%.9g,%.9g:%.9g:%.9g,%.9g",
                    d(l.position.x), d(l.position.y), d(l.position.z), d(l.direction.x), d(l.direction.y),
                    d(l.direction.z), d(l.color.r), d(l.color.g), d(l.color.b), d(l.intensity),
                    d(l.inner_cone / kDegrees), d(l.outer_cone / kDegrees));
      break;
    case SceneLight::Type::kDirectional:
      std::snprintf(buf, sizeof buf, "dir:%.9g,%.9g,%.9g:%.9g,%.9g,%.9g:%.9g", d(l.direction.x), d(l.direction.y),
                    d(l.direction.z), d(l.color.r), d(l.color.g), d(l.color.b), d(l.intensity));
      return buf;  // directional lights have no range
    case SceneLight::Type::kRect:
    case SceneLight::Type::kDisk:
      // position : emission direction : tangent (the node's +X) : colour : intensity : width,height
      std::snprintf(buf, sizeof buf, "%s:%.9g,%.9g,%.9g:%.9g,%.9g,%.9g:%.9g,%.9g,%.9g:%.9g,%.9g,%.9g:%.9g:%.9g,%.9g",
                    light_type_name(l.type), d(l.position.x), d(l.position.y), d(l.position.z), d(l.direction.x),
                    d(l.direction.y), d(l.direction.z), d(l.tangent.x), d(l.tangent.y), d(l.tangent.z), d(l.color.r),
                    d(l.color.g), d(l.color.b), d(l.intensity), d(l.width), d(l.height));
      break;
  }
  std::string out = buf;
  if (l.range > 0.0f) {
    std::snprintf(buf, sizeof buf, ":%.9g", d(l.range));
    out += buf;
  }
  return out;
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
