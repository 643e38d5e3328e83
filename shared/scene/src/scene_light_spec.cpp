// Light spec strings (--lights): parsing and printing, documented in scene.hpp and docs/scenes.md.
// Positional fields first (as they always were), then named extent fields ("radius=", "angle_deg="), so that
// every spec written before lights had an extent still parses to the same light.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>

#include "scene/scene.hpp"

namespace dhr {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kDegrees = kPi / 180.0f;

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

// The spec's shape per type: how many positional fields (kind included) it needs, and what it may add.
struct SpecShape {
  std::size_t fields = 0;         // required, counting the kind
  bool has_range = true;          // one optional positional field after them
  const char* extent_key = "";    // the named field this type accepts ("" = none)
  const char* usage = "";
};

SpecShape shape_of(SceneLight::Type type) {
  switch (type) {
    case SceneLight::Type::kPoint:
      return {4, true, "radius", "point:x,y,z:r,g,b:intensity[:range][:radius=R]"};
    case SceneLight::Type::kSpot:
      return {6, true, "radius", "spot:x,y,z:dx,dy,dz:r,g,b:intensity:inner_deg,outer_deg[:range][:radius=R]"};
    case SceneLight::Type::kDirectional:
      return {4, false, "angle_deg", "dir:dx,dy,dz:r,g,b:intensity[:angle_deg=A]"};
    case SceneLight::Type::kRect:
      return {7, true, "", "rect:x,y,z:dx,dy,dz:tx,ty,tz:r,g,b:nits:width,height[:range]"};
    case SceneLight::Type::kDisk:
      return {7, true, "", "disk:x,y,z:dx,dy,dz:tx,ty,tz:r,g,b:nits:diameter,diameter[:range]"};
  }
  return {};
}

std::optional<SceneLight::Type> type_of(std::string_view kind) {
  if (kind == "point") return SceneLight::Type::kPoint;
  if (kind == "spot") return SceneLight::Type::kSpot;
  if (kind == "dir" || kind == "directional") return SceneLight::Type::kDirectional;
  if (kind == "rect") return SceneLight::Type::kRect;
  if (kind == "disk") return SceneLight::Type::kDisk;
  return std::nullopt;
}

// Reads "key=value" fields (after the positional ones) into the light's extent.
bool parse_named(std::string_view field, const SpecShape& shape, SceneLight& light, std::string* out_error) {
  const std::size_t eq = field.find('=');
  const std::string_view key = trim(field.substr(0, eq));
  if (key != shape.extent_key || *shape.extent_key == '\0') {
    *out_error = "unknown or misplaced field \"" + std::string(field) + "\" (expected " + shape.usage + ")";
    return false;
  }
  float v = 0.0f;
  if (!parse_numbers(field.substr(eq + 1), 1, &v, shape.extent_key, out_error)) return false;
  if (key == "radius") light.radius = v;
  if (key == "angle_deg") light.angle = v * kDegrees;
  return true;
}

}  // namespace

std::optional<SceneLight> parse_light_spec(std::string_view spec, std::string* out_error) {
  std::string ignored;
  std::string& error = out_error ? *out_error : ignored;
  std::vector<std::string_view> f = split(trim(spec), ':');
  auto fail = [&](const std::string& message) -> std::optional<SceneLight> {
    error = "light spec \"" + std::string(spec) + "\": " + message;
    return std::nullopt;
  };
  const std::optional<SceneLight::Type> type = type_of(f[0]);
  if (!type) return fail("unknown light type \"" + std::string(f[0]) + "\" (use point, spot, dir, rect or disk)");
  const SpecShape shape = shape_of(*type);
  SceneLight light;
  light.type = *type;
  // Named fields trail the positional ones.
  std::size_t positional = f.size();
  while (positional > 0 && f[positional - 1].find('=') != std::string_view::npos) --positional;
  for (std::size_t i = 1; i < positional; ++i) {
    if (f[i].find('=') != std::string_view::npos)
      return fail("named field \"" + std::string(f[i]) + "\" must follow the others (expected " + shape.usage + ")");
  }
  for (std::size_t i = positional; i < f.size(); ++i) {
    if (!parse_named(f[i], shape, light, &error)) return fail(error);
  }
  if (positional != shape.fields && !(shape.has_range && positional == shape.fields + 1)) {
    return fail(std::string("expected ") + shape.usage);
  }
  float v[3];
  std::size_t next = 1;
  auto read3 = [&](const char* what, glm::vec3& out) {
    if (!parse_numbers(f[next++], 3, v, what, &error)) return false;
    out = glm::vec3(v[0], v[1], v[2]);
    return true;
  };
  if (light.type != SceneLight::Type::kDirectional && !read3("position", light.position)) return fail(error);
  if (light.type != SceneLight::Type::kPoint && !read3("direction", light.direction)) return fail(error);
  const bool area = light.type == SceneLight::Type::kRect || light.type == SceneLight::Type::kDisk;
  if (area && !read3("tangent", light.tangent)) return fail(error);
  if (!read3("colour", light.color)) return fail(error);
  if (!parse_numbers(f[next++], 1, v, "intensity", &error)) return fail(error);
  light.intensity = v[0];
  if (light.type == SceneLight::Type::kSpot) {
    if (!parse_numbers(f[next++], 2, v, "cone angles", &error)) return fail(error);
    light.inner_cone = v[0] * kDegrees;
    light.outer_cone = v[1] * kDegrees;
  }
  if (area) {
    if (!parse_numbers(f[next++], 2, v, "width,height", &error)) return fail(error);
    light.width = v[0];
    light.height = v[1];
  }
  if (next < positional) {
    if (!parse_numbers(f[next], 1, v, "range", &error)) return fail(error);
    light.range = v[0];
  }
  if (light.type != SceneLight::Type::kPoint) {
    const float len = glm::length(light.direction);
    if (!(len > 1e-6f)) return fail("the direction must not be zero");
    light.direction /= len;
  }
  if (area) {
    // Gram-Schmidt: the tangent only needs to point roughly along the width.
    const glm::vec3 t = light.tangent - glm::dot(light.tangent, light.direction) * light.direction;
    const float len = glm::length(t);
    if (!(len > 1e-3f * glm::length(light.tangent))) return fail("the tangent must not be parallel to the direction");
    light.tangent = t / len;
    light.bitangent = glm::cross(light.tangent, light.direction);  // +X x -Z = +Y: the emitter's local frame
  }
  light.name = std::string(f[0]) + "_spec";
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
      break;
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
  // Directional lights have no range.
  if (l.range > 0.0f && l.type != SceneLight::Type::kDirectional) {
    std::snprintf(buf, sizeof buf, ":%.9g", d(l.range));
    out += buf;
  }
  if (l.radius > 0.0f) {
    std::snprintf(buf, sizeof buf, ":radius=%.9g", d(l.radius));
    out += buf;
  }
  if (l.angle > 0.0f) {
    std::snprintf(buf, sizeof buf, ":angle_deg=%.9g", d(l.angle / kDegrees));
    out += buf;
  }
  return out;
}

}  // namespace dhr
