// Helpers of the client pass tests (client_*_test.cpp): hand-made scenes, views, image readback.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <vector>

#include "math/pose.hpp"
#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "vk/context.hpp"
#include "vk/image.hpp"

namespace dhr::render::test {

// A pose at `eye` looking at `target` (OpenXR eye axes: -Z forward, +Y up).
inline Pose look_at(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up = {0.0, 1.0, 0.0}) {
  const glm::dvec3 back = glm::normalize(eye - target);
  const glm::dvec3 right = glm::normalize(glm::cross(up, back));
  const glm::dvec3 true_up = glm::cross(back, right);
  Pose pose;
  pose.position = eye;
  pose.orientation = glm::normalize(glm::quat_cast(glm::dmat3(right, true_up, back)));
  return pose;
}

// A symmetric FOV with the given tangents.
inline Fov fov_from_tangents(double tan_x, double tan_y) {
  return Fov{static_cast<float>(-std::atan(tan_x)), static_cast<float>(std::atan(tan_x)),
             static_cast<float>(std::atan(tan_y)), static_cast<float>(-std::atan(tan_y))};
}

// Rotation of `pose` by yaw (about +Y) then pitch (about the eye's +X), degrees.
inline Pose rotated(Pose pose, double yaw_deg, double pitch_deg) {
  const glm::dquat yaw = glm::angleAxis(glm::radians(yaw_deg), glm::dvec3(0.0, 1.0, 0.0));
  const glm::dquat pitch = glm::angleAxis(glm::radians(pitch_deg), glm::dvec3(1.0, 0.0, 0.0));
  pose.orientation = glm::normalize(yaw * pose.orientation * pitch);
  return pose;
}

// A material with a colour factor (no texture).
inline SceneMaterial colour_material(const glm::vec4& colour, bool double_sided = false) {
  SceneMaterial m;
  m.name = "colour";
  m.base_color_factor = colour;
  m.double_sided = double_sided;
  return m;
}

// A quad (two triangles) with corners c0..c3 counter-clockwise seen from its front; flat normal.
inline SceneMesh quad_mesh(const glm::dvec3& c0, const glm::dvec3& c1, const glm::dvec3& c2, const glm::dvec3& c3,
                           uint32_t material) {
  SceneMesh mesh;
  mesh.name = "quad";
  mesh.material = material;
  mesh.positions = {glm::vec3(c0), glm::vec3(c1), glm::vec3(c2), glm::vec3(c3)};
  const glm::vec3 n = glm::vec3(glm::normalize(glm::cross(c1 - c0, c2 - c0)));
  mesh.normals = {n, n, n, n};
  mesh.texcoords = {{0.0f, 1.0f}, {1.0f, 1.0f}, {1.0f, 0.0f}, {0.0f, 0.0f}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

inline void finish_scene(Scene& scene) {
  scene.bounds = SceneBounds{};
  scene.triangle_count = 0;
  scene.vertex_count = 0;
  for (const SceneMesh& m : scene.meshes) {
    for (const glm::vec3& p : m.positions) scene.bounds.extend(p);
    scene.triangle_count += m.triangle_count();
    scene.vertex_count += m.positions.size();
  }
}

// IEEE half -> float.
inline float half_to_float(uint16_t h) {
  const uint32_t sign = (h >> 15) & 1u, exponent = (h >> 10) & 0x1Fu, mantissa = h & 0x3FFu;
  float value = 0.0f;
  if (exponent == 0) {
    value = std::ldexp(static_cast<float>(mantissa), -24);
  } else if (exponent == 31) {
    value = mantissa == 0 ? INFINITY : NAN;
  } else {
    value = std::ldexp(static_cast<float>(mantissa | 0x400u), static_cast<int>(exponent) - 25);
  }
  return sign != 0 ? -value : value;
}

template <typename T>
std::vector<T> read_pixels(const vk::Context& context, vk::Image& image, size_t components = 1) {
  std::vector<T> out(size_t{image.width()} * image.height() * components);
  vk::read_image(context, image, out.data(), out.size() * sizeof(T));
  return out;
}

// RGBA16F normals as floats (4 per pixel).
inline std::vector<float> read_normals(const vk::Context& context, vk::Image& image) {
  const std::vector<uint16_t> raw = read_pixels<uint16_t>(context, image, 4);
  std::vector<float> out(raw.size());
  for (size_t i = 0; i < raw.size(); ++i) out[i] = half_to_float(raw[i]);
  return out;
}

// The same as world normal vectors (what the CPU warp reference takes).
inline std::vector<glm::vec3> read_normal_vectors(const vk::Context& context, vk::Image& image) {
  const std::vector<float> raw = read_normals(context, image);
  std::vector<glm::vec3> out(raw.size() / 4);
  for (size_t i = 0; i < out.size(); ++i) out[i] = glm::vec3(raw[i * 4], raw[i * 4 + 1], raw[i * 4 + 2]);
  return out;
}

}  // namespace dhr::render::test
