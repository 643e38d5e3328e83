// Display encoding of the client's shading pass, shared by GLSL (shading.comp) and C++ (tests, tools):
// linear radiance -> exposure -> ACES filmic approximation (Narkowicz 2015, per channel) -> sRGB encoding.
// The result is written as bytes into an RGBA8_UNORM storage image; the bytes are sRGB-encoded, so a copy
// (not a blit) into an R8G8B8A8_SRGB swapchain image shows them unchanged.
// Common subset of GLSL 4.5 and C++20 with GLM, as light_eval.h; both include it as "shaders/display_encode.h".
#ifndef DHR_DISPLAY_ENCODE_H
#define DHR_DISPLAY_ENCODE_H

#ifdef __cplusplus
#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/vec3.hpp>
#define DE_FN inline
namespace dhr::display_encode {
using glm::clamp;
using glm::max;
using glm::pow;
using glm::vec3;
#else
#define DE_FN
#endif

// Filmic curve: maps [0, inf) to [0, 1), close to linear (slope ~0.2 at 0) for dark values.
DE_FN float tonemap_aces(float x) {
  const float v = max(x, 0.0f);
  return clamp((v * (2.51f * v + 0.03f)) / (v * (2.43f * v + 0.59f) + 0.14f), 0.0f, 1.0f);
}

// IEC 61966-2-1 sRGB transfer function for c in [0, 1].
DE_FN float srgb_encode(float c) {
  return c <= 0.0031308f ? 12.92f * c : 1.055f * pow(c, 1.0f / 2.4f) - 0.055f;
}

// Linear scene radiance -> display-referred sRGB-encoded value in [0, 1] per channel.
DE_FN vec3 encode_radiance(vec3 radiance, float exposure) {
  return vec3(srgb_encode(tonemap_aces(radiance.x * exposure)), srgb_encode(tonemap_aces(radiance.y * exposure)),
              srgb_encode(tonemap_aces(radiance.z * exposure)));
}

#ifdef __cplusplus
}  // namespace dhr::display_encode
#endif

#undef DE_FN
#endif  // DHR_DISPLAY_ENCODE_H
