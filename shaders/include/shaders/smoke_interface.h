// The ray-tracing smoke test's interface (shaders/smoke/, tests/vulkan/ray_tracing_test.cpp), shared by GLSL and
// C++ as shader_interface.h is (the same conventions: 4-byte scalars, namespace dhr::shader in C++): an orthographic
// grid of rays along -z through a TLAS, one SmokeHit per ray.
#ifndef DHR_SMOKE_INTERFACE_H
#define DHR_SMOKE_INTERFACE_H

#ifdef __cplusplus
#include <cstdint>
namespace dhr::shader {
using uint = std::uint32_t;
#define DHR_SMOKE_CONST constexpr
#else
#define DHR_SMOKE_CONST const
#endif

DHR_SMOKE_CONST uint kSmokeBindingTlas = 0;    // accelerationStructureEXT
DHR_SMOKE_CONST uint kSmokeBindingResults = 1; // storage buffer of SmokeHit[width * height]

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

#undef DHR_SMOKE_CONST
#endif  // DHR_SMOKE_INTERFACE_H
