// Shared by GLSL and C++: descriptor binding numbers, push-constant and result structs.
// GLSL sees plain `const uint` and structs; C++ sees the same names in namespace dhr::shader with
// fixed-width types. Keep members 4-byte scalars (no vec3) so std430/scalar and C++ layouts agree.
#ifndef DHR_SHADER_INTERFACE_H
#define DHR_SHADER_INTERFACE_H

#ifdef __cplusplus
#include <cstdint>
#define DHR_CONST constexpr
namespace dhr::shader {
using uint = std::uint32_t;
#else
#define DHR_CONST const
#endif

// ---- smoke test (tests/vulkan): orthographic grid of rays along -z through a TLAS ----
DHR_CONST uint kSmokeBindingTlas = 0;    // accelerationStructureEXT
DHR_CONST uint kSmokeBindingResults = 1; // storage buffer of SmokeHit[width * height]

struct SmokePushConstants {
  float grid_min_x;   // ray (i, j) starts at (grid_min_x + (i + 0.5) * step_x,
  float grid_min_y;   //                       grid_min_y + (j + 0.5) * step_y, origin_z)
  float step_x;
  float step_y;
  float origin_z;
  float t_min;
  float t_max;
  uint width;
  uint height;
  uint cull_mask;     // ANDed with each instance's mask
};

struct SmokeHit {
  uint hit;           // 1: closest hit found, 0: miss
  float t;            // hit distance (direction has unit length)
  uint primitive_id;  // gl_PrimitiveID
  uint custom_index;  // gl_InstanceCustomIndexEXT
};

#ifdef __cplusplus
static_assert(sizeof(SmokePushConstants) == 40, "push constants must match the GLSL layout");
static_assert(sizeof(SmokeHit) == 16, "SmokeHit must match the std430 array stride");
}  // namespace dhr::shader
#endif

#undef DHR_CONST
#endif  // DHR_SHADER_INTERFACE_H
