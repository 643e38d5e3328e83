#include "scene/lighting.hpp"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

namespace dhr {

PackedLight pack_light(const SceneLight& light, const glm::dvec3& origin) {
  PackedLight p{};
  // Sphere lights and the sun disk pack as their punctual type: their extent only softens shadows.
  float type = light_eval::kLightTypePoint;
  float intensity = light.intensity;
  switch (light.type) {
    case SceneLight::Type::kPoint:
      break;
    case SceneLight::Type::kSpot:
      type = light_eval::kLightTypeSpot;
      break;
    case SceneLight::Type::kDirectional:
      type = light_eval::kLightTypeDirectional;
      break;
    case SceneLight::Type::kRect:
    case SceneLight::Type::kDisk:
      // A Lambertian emitter of luminance L (nits) and area A has intensity L * A * cos (candela) at a distance.
      type = light.type == SceneLight::Type::kRect ? light_eval::kLightTypeRect : light_eval::kLightTypeDisk;
      intensity = light.intensity * light.area();
      break;
  }
  const glm::dvec3 position = glm::dvec3(light.position) - origin;
  p.position_type = glm::vec4(glm::vec3(position), type);
  p.direction_range = glm::vec4(light.direction, std::max(light.range, 0.0f));
  p.color_intensity = glm::vec4(light.color, intensity);
  // glTF's spot falloff: saturate(cd * scale + offset)^2 is 0 at the outer cone and 1 at the inner one.
  const double cos_outer = std::cos(static_cast<double>(light.outer_cone));
  const double cos_inner = std::cos(static_cast<double>(light.inner_cone));
  const double scale = 1.0 / std::max(1e-3, cos_inner - cos_outer);
  p.spot = glm::vec4(static_cast<float>(cos_outer), static_cast<float>(scale),
                     static_cast<float>(-cos_outer * scale), 0.0f);
  return p;
}

std::vector<PackedLight> pack_lights(std::span<const SceneLight> lights, const glm::dvec3& origin) {
  std::vector<PackedLight> out;
  out.reserve(lights.size());
  for (const SceneLight& light : lights) out.push_back(pack_light(light, origin));
  return out;
}

glm::vec3 light_contribution(const PackedLight& light, const LightSample& sample, const glm::vec3& n) {
  if (sample.test != LightTest::kContributes) return glm::vec3(0.0f);
  return light_eval::light_irradiance(light, sample.l, sample.distance) * light_eval::light_cosine(n, sample.l);
}

bool light_may_reach_view(const SceneLight& light, const Camera& camera) {
  if (light.type == SceneLight::Type::kDirectional || !(light.range > 0.0f)) return true;
  // Light centre in eye space (double): +X right, +Y up, -Z forward; depth = -z.
  const glm::dvec3 c = glm::conjugate(camera.T_world_eye.orientation) *
                       (glm::dvec3(light.position) - camera.T_world_eye.position);
  const Tangents& t = camera.tangents;
  // Inward plane normals through the eye: a point q is inside when dot(n, q) >= 0 for all of them.
  const glm::dvec3 planes[5] = {
      {1.0, 0.0, t.left},     // x >= left * depth
      {-1.0, 0.0, -t.right},  // x <= right * depth
      {0.0, -1.0, -t.up},     // y <= up * depth
      {0.0, 1.0, t.down},     // y >= down * depth
      {0.0, 0.0, -1.0},       // depth >= 0
  };
  // Margin for the float arithmetic of the tracers (points and distances are evaluated in float).
  const double range = static_cast<double>(light.range);
  const double margin = range * 1e-4 + 1e-4 + 1e-6 * glm::length(c);
  for (const glm::dvec3& n : planes) {
    if (glm::dot(n, c) / glm::length(n) < -(range + margin)) return false;
  }
  return true;
}

}  // namespace dhr
