#include "preview_shading.hpp"

#include "scene/lighting.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>

namespace dhr::server::cli {
namespace {

constexpr float kPi = 3.14159265f;
constexpr float kAmbient = 0.03f;  // fraction of the albedo shown in full shadow (display only)
const glm::vec3 kBackground(0.02f, 0.025f, 0.035f);

float srgb_to_linear(uint8_t v) {
  const float c = static_cast<float>(v) / 255.0f;
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

uint8_t linear_to_srgb8(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  const float s = c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
  return static_cast<uint8_t>(std::lround(s * 255.0f));
}

float wrap_coordinate(float t, TextureWrap wrap) {
  if (!std::isfinite(t)) return 0.0f;
  switch (wrap) {
    case TextureWrap::kClampToEdge: return std::clamp(t, 0.0f, 1.0f);
    case TextureWrap::kMirroredRepeat: {
      const float m = t - 2.0f * std::floor(t * 0.5f);  // [0, 2)
      return m > 1.0f ? 2.0f - m : m;
    }
    case TextureWrap::kRepeat: break;
  }
  return t - std::floor(t);
}

}  // namespace

glm::vec3 albedo_at(const Scene& scene, const SurfaceHit& hit) {
  const SceneMesh& mesh = scene.meshes[hit.mesh];
  if (mesh.material >= scene.materials.size()) return glm::vec3(0.8f);
  const SceneMaterial& material = scene.materials[mesh.material];
  glm::vec3 albedo(material.base_color_factor);
  const int32_t image_index = material.base_color_image;
  if (image_index < 0 || static_cast<size_t>(image_index) >= scene.images.size() ||
      mesh.texcoords.size() != mesh.positions.size())
    return albedo;
  const SceneImage& image = scene.images[static_cast<size_t>(image_index)];
  if (image.width == 0 || image.height == 0 || image.rgba8.size() < size_t{4} * image.width * image.height)
    return albedo;
  const uint32_t* idx = &mesh.indices[3 * static_cast<size_t>(hit.triangle)];
  const float w = 1.0f - hit.u - hit.v;
  const glm::vec2 uv = w * mesh.texcoords[idx[0]] + hit.u * mesh.texcoords[idx[1]] + hit.v * mesh.texcoords[idx[2]];
  const float s = wrap_coordinate(uv.x, material.wrap_s), t = wrap_coordinate(uv.y, material.wrap_t);
  const uint32_t x = std::min(image.width - 1, static_cast<uint32_t>(s * static_cast<float>(image.width)));
  const uint32_t y = std::min(image.height - 1, static_cast<uint32_t>(t * static_cast<float>(image.height)));
  const uint8_t* texel = &image.rgba8[4 * (static_cast<size_t>(y) * image.width + x)];
  return albedo * glm::vec3(srgb_to_linear(texel[0]), srgb_to_linear(texel[1]), srgb_to_linear(texel[2]));
}

std::vector<uint8_t> shade_preview(const Scene& scene, const EmbreeScene& embree, const Camera& camera,
                                   const VisibilityBuffer& visibility) {
  const uint32_t width = camera.extent.width, height = camera.extent.height;
  const std::vector<PackedLight> lights = pack_lights(scene.lights, embree.origin());
  const glm::dmat3 world_from_eye = glm::mat3_cast(glm::normalize(camera.T_world_eye.orientation));
  const glm::vec3 eye = embree.to_relative(camera.T_world_eye.position);

  std::vector<glm::vec3> direct(static_cast<size_t>(width) * height, glm::vec3(0.0f));
  std::vector<glm::vec3> albedo(direct.size(), glm::vec3(-1.0f));  // < 0: background
  std::vector<float> luminance;
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      const glm::vec3 dir(glm::normalize(world_from_eye * camera.eye_ray(x + 0.5, y + 0.5)));
      const float tnear =
          static_cast<float>(kClipNearPlane / glm::dot(glm::dvec3(dir), world_from_eye * glm::dvec3(0, 0, -1)));
      const auto hit = embree.intersect(eye, dir, tnear);  // from the near plane, as the tracers do
      if (!hit) continue;
      albedo[i] = albedo_at(scene, *hit);
      const uint32_t mask = visibility.width == width && visibility.height == height ? visibility.get(x, y) : 0u;
      glm::vec3 e(0.0f);
      for (uint32_t li = 0; li < lights.size(); ++li) {
        if (!(mask >> li & 1u)) continue;
        e += light_contribution(lights[li], sample_light(lights[li], hit->position, hit->shading_normal),
                                hit->shading_normal);
      }
      direct[i] = albedo[i] / kPi * e;
      const float lum = glm::dot(direct[i], glm::vec3(0.2126f, 0.7152f, 0.0722f));
      if (lum > 0.0f && std::isfinite(lum)) luminance.push_back(lum);
    }
  }
  // Auto exposure: the 95th percentile of lit pixels maps to ~0.6 before sRGB.
  float exposure = 1.0f;
  if (!luminance.empty()) {
    const size_t k = luminance.size() * 95 / 100;
    std::nth_element(luminance.begin(), luminance.begin() + static_cast<std::ptrdiff_t>(k), luminance.end());
    exposure = 1.5f / luminance[k];
  }
  std::vector<uint8_t> rgb(direct.size() * 3);
  for (size_t i = 0; i < direct.size(); ++i) {
    glm::vec3 c = kBackground;
    if (albedo[i].x >= 0.0f) {
      const glm::vec3 x = direct[i] * exposure;
      c = x / (glm::vec3(1.0f) + x) + kAmbient * albedo[i];
    }
    for (int ch = 0; ch < 3; ++ch) rgb[3 * i + static_cast<size_t>(ch)] = linear_to_srgb8(c[ch]);
  }
  return rgb;
}

}  // namespace dhr::server::cli
