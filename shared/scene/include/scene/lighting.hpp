// C++ side of the shared light math (shaders/include/shaders/light_eval.h): packing SceneLights for
// evaluation and upload, the per-point light test, and per-view light culling. The GLSL shaders include the
// same header, so the CPU and GPU decide "this light can contribute here" identically.
#pragma once
#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "shaders/light_eval.h"  // dhr_shader_headers: the GLSL shaders include this same file

#include <glm/vec3.hpp>

#include <span>
#include <vector>

namespace dhr {

using light_eval::PackedLight;
static_assert(sizeof(PackedLight) == 64, "PackedLight must match the GLSL std430 layout");

// Why a light cannot contribute at a point (values equal light_eval's kLight* constants).
enum class LightTest : int {
  kContributes = light_eval::kLightContributes,
  kOutOfRange = light_eval::kLightOutOfRange,
  kBackfacing = light_eval::kLightBackfacing,
};

// The light in the frame whose origin is `origin` (world), subtracted in double so the packed float
// position keeps precision near that origin.
PackedLight pack_light(const SceneLight& light, const glm::dvec3& origin = glm::dvec3(0.0));
std::vector<PackedLight> pack_lights(std::span<const SceneLight> lights, const glm::dvec3& origin = glm::dvec3(0.0));

struct LightSample {
  LightTest test = LightTest::kOutOfRange;
  glm::vec3 l{0.0f, 1.0f, 0.0f};  // unit direction toward the light
  float distance = 0.0f;          // light_eval::kLightInfiniteDistance for directional lights
};

// light_eval::light_test for a point p with unit normal n (both in the light's packing frame).
inline LightSample sample_light(const PackedLight& light, const glm::vec3& p, const glm::vec3& n) {
  LightSample s;
  s.test = static_cast<LightTest>(light_eval::light_test(light, p, n, s.l, s.distance));
  return s;
}

// E * saturate(N.L) of a sample (zero unless it contributes).
glm::vec3 light_contribution(const PackedLight& light, const LightSample& sample, const glm::vec3& n);

// False when the light provably contributes nothing to any surface point the camera can see: a point
// or spot light with a finite range whose range sphere lies entirely outside the camera's frustum
// (its four side planes and the eye plane; the camera's tangents include any guard band). Conservative:
// true whenever unsure, so culling never changes a visibility bit.
bool light_may_reach_view(const SceneLight& light, const Camera& camera);

}  // namespace dhr
