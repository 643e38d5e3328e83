// Lights from glTF: KHR_lights_punctual (with the extent in extras.radius / extras.angle) and EXT_lights_area
// (KhronosGroup glTF PR 2525: rect and disk, intensity in nits, size scaled by the node's largest world scale).
// Values are read from the raw JSON (LightJson), not tinygltf's copy, which drops null members silently.
// The JSON validator leaves these lenient on purpose: a bad light value costs that light (or its extent) with a
// warning naming it, never the whole scene (DESIGN 5b: never silently, never a crash).
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <nlohmann/json.hpp>

#include "scene_internal.hpp"

namespace dhr::scene_detail {
namespace {

// EXT_lights_area's defaults (PR 2525): 1000 nits, size 1, aspect 1.
constexpr double kDefaultNits = 1000.0;
// The same bound the validator puts on KHR_lights_punctual intensities.
constexpr double kMaxIntensity = 1.0e30;

glm::vec3 normalized_or(const glm::dvec3& v, const glm::vec3& fallback) {
  const double len = glm::length(v);
  if (!(len > 1e-12) || !std::isfinite(len)) return fallback;
  return glm::vec3(v / len);
}

using Json = nlohmann::json;

// A JSON value for a warning: the number, or what kind of value it is.
std::string describe(const Json& v) {
  if (v.is_number()) return format("%g", v.get<double>());
  if (v.is_string()) return "\"" + v.get<std::string>() + "\"";
  if (v.is_null()) return "null";
  return v.type_name() + std::string(v.is_array() || v.is_object() ? "" : " value");
}
std::string describe(const tinygltf::Value& v) {
  if (v.IsNumber()) return format("%g", v.GetNumberAsDouble());
  if (v.IsString()) return "\"" + v.Get<std::string>() + "\"";
  return v.IsArray() ? "an array" : v.IsObject() ? "an object" : "null";
}

// A number in [lo, hi] (finite), or nullopt.
std::optional<double> number_in(const Json& v, double lo, double hi) {
  if (!v.is_number()) return std::nullopt;
  const double x = v.get<double>();
  if (!std::isfinite(x) || x < lo || x > hi) return std::nullopt;
  return x;
}

// A positive, finite number, or nullopt.
std::optional<double> positive(const Json& v) {
  if (!v.is_number()) return std::nullopt;
  const double x = v.get<double>();
  if (!std::isfinite(x) || !(x > 0.0)) return std::nullopt;
  return x;
}

// The JSON text extract_light_json kept ("" = absent -> null).
Json parse_kept(const std::string& text) { return text.empty() ? Json() : Json::parse(text); }

std::string light_label(const char* kind, std::size_t index, const std::string& name) {
  return format("%s %zu ('%s')", kind, index, name.c_str());
}

// extras.radius / extras.angle of one KHR_lights_punctual light; each bad value is named and ignored.
PunctualExtent read_extent(const tinygltf::Light& src, const Json& extras, std::size_t index, WarningSink& warnings) {
  PunctualExtent e;
  if (!extras.is_object()) return e;
  const std::string label = light_label("light", index, src.name);
  const bool directional = src.type == "directional";
  if (auto it = extras.find("radius"); it != extras.end()) {
    if (directional) {
      warnings.add(label + ": extras.radius is for point and spot lights (a sun takes extras.angle); ignored");
    } else if (const auto r = number_in(*it, 0.0, kMaxLightExtent)) {
      e.radius = static_cast<float>(*r);
    } else {
      warnings.add(format("%s: extras.radius %s is not a number of metres in [0, %g]; ignored, the light stays "
                          "punctual",
                          label.c_str(), describe(*it).c_str(), static_cast<double>(kMaxLightExtent)));
    }
  }
  if (auto it = extras.find("angle"); it != extras.end()) {
    if (!directional) {
      warnings.add(label + ": extras.angle is for directional lights (a point or spot takes extras.radius); ignored");
    } else if (const auto a = number_in(*it, 0.0, kMaxLightAngle)) {
      e.angle = static_cast<float>(*a);
    } else {
      warnings.add(format("%s: extras.angle %s is not an angular diameter in [0, %g] rad; ignored, the light stays "
                          "punctual",
                          label.c_str(), describe(*it).c_str(), static_cast<double>(kMaxLightAngle)));
    }
  }
  return e;
}

// One EXT_lights_area definition; `usable` false (after a warning) when a value is unusable.
AreaLightDef read_area_def(const Json& v, std::size_t index, WarningSink& warnings) {
  AreaLightDef def;
  if (!v.is_object()) {
    warnings.add(format("EXT_lights_area light %zu is %s, not an object; skipped", index, describe(v).c_str()));
    return def;
  }
  if (auto n = v.find("name"); n != v.end() && n->is_string()) def.name = n->get<std::string>();
  const std::string label = light_label("EXT_lights_area light", index, def.name);
  auto skip = [&](const std::string& what) {
    warnings.add(label + ": " + what + "; the light is skipped");
    return def;
  };
  const Json type = v.value("type", Json());
  if (type == "rect") {
    def.type = SceneLight::Type::kRect;
  } else if (type == "disk") {
    def.type = SceneLight::Type::kDisk;
  } else {
    return skip("unknown type " + describe(type) + " (rect or disk)");
  }
  if (auto c = v.find("color"); c != v.end()) {
    std::optional<double> rgb[3];
    for (std::size_t i = 0; c->is_array() && c->size() == 3 && i < 3; ++i)
      rgb[i] = number_in((*c)[i], 0.0, kMaxIntensity);
    if (!rgb[0] || !rgb[1] || !rgb[2]) return skip("color is not 3 finite, non-negative numbers");
    def.color = glm::vec3(static_cast<float>(*rgb[0]), static_cast<float>(*rgb[1]), static_cast<float>(*rgb[2]));
  }
  def.nits = kDefaultNits;
  if (auto i = v.find("intensity"); i != v.end()) {
    const auto nits = number_in(*i, 0.0, kMaxIntensity);
    if (!nits) return skip("intensity " + describe(*i) + " is not a luminance in nits (>= 0)");
    def.nits = *nits;
  }
  if (auto s = v.find("size"); s != v.end()) {
    const auto size = positive(*s);
    if (!size) return skip("size " + describe(*s) + " is not a positive number");
    def.size = *size;
  }
  if (auto r = v.find("rect"); def.type == SceneLight::Type::kRect && r != v.end() && r->is_object()) {
    if (auto a = r->find("aspect"); a != r->end()) {
      const auto aspect = positive(*a);
      if (!aspect) return skip("rect.aspect " + describe(*a) + " is not a positive number");
      def.aspect = *aspect;
    }
  }
  def.usable = true;
  return def;
}

// Gram-Schmidt of v against the unit vectors `against`; nullopt when nothing is left (a degenerate transform).
std::optional<glm::dvec3> orthonormal(glm::dvec3 v, std::initializer_list<glm::dvec3> against) {
  for (const glm::dvec3& a : against) v -= glm::dot(v, a) * a;
  const double len = glm::length(v);
  if (!(len > 1e-9) || !std::isfinite(len)) return std::nullopt;
  return v / len;
}

}  // namespace

LightJson extract_light_json(const Json& root) {
  LightJson out;
  const Json* ext = root.contains("extensions") ? &root["extensions"] : nullptr;
  if (ext && ext->is_object() && ext->contains("EXT_lights_area")) out.area = (*ext)["EXT_lights_area"].dump();
  if (!ext || !ext->is_object() || !ext->contains("KHR_lights_punctual")) return out;
  const Json& lights = (*ext)["KHR_lights_punctual"].value("lights", Json::array());
  for (const Json& light : lights) {
    const auto extras = light.is_object() ? light.find("extras") : light.end();
    out.extras.push_back(light.is_object() && extras != light.end() ? extras->dump() : std::string());
  }
  return out;
}

std::vector<PunctualExtent> read_punctual_extents(const tinygltf::Model& model, const LightJson& json,
                                                  WarningSink& warnings) {
  std::vector<PunctualExtent> out;
  out.reserve(model.lights.size());
  for (std::size_t i = 0; i < model.lights.size(); ++i) {
    const Json extras = i < json.extras.size() ? parse_kept(json.extras[i]) : Json();
    out.push_back(read_extent(model.lights[i], extras, i, warnings));
  }
  return out;
}

SceneLight light_from_gltf(const tinygltf::Model& model, int index, const glm::dmat4& T_world_node,
                           const PunctualExtent& extent) {
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
  // KHR_lights_punctual lights ignore the node's scale, so the radius (metres) does too.
  light.radius = extent.radius;
  light.angle = extent.angle;
  return light;
}

std::vector<AreaLightDef> read_area_lights(const LightJson& json, WarningSink& warnings) {
  std::vector<AreaLightDef> defs;
  if (json.area.empty()) return defs;
  const Json area = parse_kept(json.area);
  const Json lights = area.value("lights", Json());
  if (!lights.is_array()) {
    warnings.add("EXT_lights_area: \"lights\" is " + describe(lights) + ", not an array; no area light is read");
    return defs;
  }
  for (std::size_t i = 0; i < lights.size(); ++i) defs.push_back(read_area_def(lights[i], i, warnings));
  return defs;
}

std::optional<SceneLight> area_light_from_gltf(const std::vector<AreaLightDef>& defs, const tinygltf::Value& node_ext,
                                               int node, const glm::dmat4& T_world_node, WarningSink& warnings) {
  const tinygltf::Value& ref = node_ext.Get("light");
  const double index = ref.IsNumber() ? ref.GetNumberAsDouble() : -1.0;
  if (!(index >= 0.0) || index != std::floor(index) || index >= static_cast<double>(defs.size())) {
    warnings.add(format("nodes[%d]: EXT_lights_area light %s does not exist (the file defines %zu); ignored", node,
                        describe(ref).c_str(), defs.size()));
    return std::nullopt;
  }
  const AreaLightDef& def = defs[static_cast<std::size_t>(index)];
  if (!def.usable) return std::nullopt;  // its definition was already warned about
  const std::string label =
      format("nodes[%d]: EXT_lights_area light %zu ('%s')", node, static_cast<std::size_t>(index), def.name.c_str());
  // PR 2525: the size is scaled by the largest absolute component of the node's world scale (uniformly).
  const glm::dmat3 m(T_world_node);
  const double scale = std::max({glm::length(m[0]), glm::length(m[1]), glm::length(m[2])});
  const double height = def.size * scale;
  const double width = def.type == SceneLight::Type::kRect ? height * def.aspect : height;
  if (!(width > 0.0 && height > 0.0) || !std::isfinite(width) || !std::isfinite(height)) {
    warnings.add(label + ": its world size is zero (a zero node scale?); the light is skipped");
    return std::nullopt;
  }
  if (width > double{kMaxLightExtent} || height > double{kMaxLightExtent}) {
    warnings.add(format("%s: %g x %g m is larger than %g m; the light is skipped", label.c_str(), width, height,
                        static_cast<double>(kMaxLightExtent)));
    return std::nullopt;
  }
  // Emits along the node's -Z; +X spans the width, +Y the height (orthonormalized against shear).
  const auto d = orthonormal(m * glm::dvec3(0.0, 0.0, -1.0), {});
  const auto t = d ? orthonormal(m[0], {*d}) : std::nullopt;
  const auto b = t ? orthonormal(m[1], {*d, *t}) : std::nullopt;
  if (!b) {
    warnings.add(label + ": the node's transform is degenerate (no emitting direction); the light is skipped");
    return std::nullopt;
  }
  SceneLight light;
  light.type = def.type;
  light.name = def.name.empty() ? format("area_light%zu", static_cast<std::size_t>(index)) : def.name;
  light.position = glm::vec3(T_world_node[3]);
  light.direction = glm::vec3(*d);
  light.tangent = glm::vec3(*t);
  light.bitangent = glm::vec3(*b);
  light.color = def.color;
  light.intensity = static_cast<float>(def.nits);
  light.width = static_cast<float>(width);
  light.height = static_cast<float>(height);
  return light;
}

}  // namespace dhr::scene_detail
