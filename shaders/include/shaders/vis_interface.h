// The server visibility tracer's part of shaders/shader_interface.h (server/vulkan_tracer*.cpp, shaders/server/):
// included by it, inside its conventions (DHR_CONST, namespace dhr::shader in C++); include that header instead.
#ifndef DHR_SHADER_INTERFACE_H
#error "include shaders/shader_interface.h, which includes this part"
#endif
#ifndef DHR_VIS_INTERFACE_H
#define DHR_VIS_INTERFACE_H

// ---- server visibility tracer (server/vulkan_tracer*.cpp, shaders/server/) ----
// Everything is in the scene-relative frame (world minus the scene's bounding-box centre, in double).
DHR_CONST uint kVisBindingTlas = 0;         // accelerationStructureEXT
DHR_CONST uint kVisBindingLights = 1;       // PackedLight[] (light_eval.h), scene-relative
DHR_CONST uint kVisBindingMeshes = 2;       // VisMesh[], indexed by gl_InstanceCustomIndexEXT
DHR_CONST uint kVisBindingPositions = 3;    // float[] x, y, z per vertex, all meshes (VisMesh::vertex_offset)
DHR_CONST uint kVisBindingNormals = 4;      // float[] x, y, z per vertex (unit or zero)
DHR_CONST uint kVisBindingIndices = 5;      // uint[] 3 per triangle in the scene's order, mesh-local vertices
DHR_CONST uint kVisBindingPermutation = 6;  // uint[] BLAS primitive -> original triangle (spatial sort)
DHR_CONST uint kVisBindingMasks = 7;        // uint[width * height]: one 32-bit light mask per pixel
DHR_CONST uint kVisBindingCounters = 8;     // uint[kVisCounterSlots * kVisCounterStride]
DHR_CONST uint kVisBindingSoftLights = 9;   // VisSoftLight[], one per scene light (its extent), scene-relative
// uint[]: with kVisLightSlots, the light slots (scene/light_slots.hpp): kVisSlotHeaderWords of header (the grid's
// origin, scene-relative, and cell edge in mm as float bits; its cells per axis; the fields per row), then per cell
// (x fastest) and one row for outside the grid, the light of each field (kVisNoSlotLight: none).
DHR_CONST uint kVisBindingLightSlots = 10;
DHR_CONST uint kVisSlotHeaderWords = 8u;
DHR_CONST uint kVisNoSlotLight = 0xFFFFu;

// Statistics counters; each pixel adds to slot (x % kVisCounterSlots) so atomics rarely collide.
DHR_CONST uint kVisCounterPrimary = 0;
DHR_CONST uint kVisCounterBackground = 1;
DHR_CONST uint kVisCounterShadow = 2;
DHR_CONST uint kVisCounterSkippedBackfacing = 3;
DHR_CONST uint kVisCounterSkippedOutOfRange = 4;
DHR_CONST uint kVisCounterSoftPairs = 5;        // TraceStats::soft_pairs
DHR_CONST uint kVisCounterSoftContributing = 6; // TraceStats::soft_contributing_pairs
DHR_CONST uint kVisCounterSoftRefined = 7;      // TraceStats::soft_refined_pairs
DHR_CONST uint kVisCounterSoftShadow = 8;       // TraceStats::soft_shadow_rays (also in kVisCounterShadow)
DHR_CONST uint kVisCounterStride = 16;  // counters per slot (9 used)
DHR_CONST uint kVisCounterSlots = 64;

// Shadow rays (same numbers as server/trace/include/trace/ray_offset.hpp and the Embree backend; vulkan_tracer.cpp checks them):
// origins move off the surface by kVisRayOffsetIntScale ULPs per unit normal, or by
// kVisRayOffsetFloatScale per unit normal where |coordinate| < kVisRayOffsetOriginThreshold (both of these
// times VisPushConstants::ray_offset_scale, a power of two for the scene's size); point and
// spot shadow rays stop at kVisShadowTfarScale of the distance so geometry at the light does not occlude it.
DHR_CONST float kVisRayOffsetOriginThreshold = 1.0f / 32.0f;
DHR_CONST float kVisRayOffsetFloatScale = 1.0f / 65536.0f;
DHR_CONST float kVisRayOffsetIntScale = 256.0f;
DHR_CONST float kVisShadowTfarScale = 1.0f - 1e-5f;

// VisPushConstants::flags
DHR_CONST uint kVisSkipBackfacing = 1u;
DHR_CONST uint kVisSkipOutOfRange = 2u;
// Fields are light slots: field f of a pixel holds the light its cell gives slot f, and a hard field is 1 where
// that light cannot contribute (or there is none), 0 only where it contributes and its ray is occluded.
DHR_CONST uint kVisLightSlots = 4u;
// VisMesh::flags
DHR_CONST uint kVisMeshDoubleSided = 1u;

// Soft lights (VisibilityTracer::trace_layout with level fields; server/trace/include/trace/soft/): a light whose bit
// is set in VisPushConstants::soft_lights has a field of kVisSoftFieldBits bits, the Gray code of its sampled
// visibility quantized to kVisSoftLevels levels. Fields follow the lights' order without gaps (VisibilityLayout), so
// light i's field starts at i + (kVisSoftFieldBits - 1) * (soft lights before i).
DHR_CONST uint kVisSoftFieldBits = 3u;
DHR_CONST uint kVisSoftLevels = 8u;
// VisSoftLight::shape (SampledLight::Shape in trace/soft/light_sampler.hpp)
DHR_CONST uint kVisSoftPunctual = 0u;  // no extent: the hard tracer's one ray
DHR_CONST uint kVisSoftSphere = 1u;    // cone sampling of the cap the sphere covers
DHR_CONST uint kVisSoftSunDisk = 2u;   // cone of half-angle angle / 2 around the direction toward the sun
DHR_CONST uint kVisSoftRect = 3u;      // uniform over its area, one-sided
DHR_CONST uint kVisSoftDisk = 4u;      // uniform over its area (concentric map), one-sided

// A light prepared for sampling (make_sampled_light), in the scene-relative frame.
struct VisSoftLight {
  uint shape;               // kVisSoft*
  uint seed;                // scramble seed of its samples, the same for every pixel (SoftPattern::kPerLight)
  float radius;             // sphere
  float sun_one_minus_cos;  // sun: 1 - cos(angle / 2)
  float centre_x;           // sphere, rect, disk
  float centre_y;
  float centre_z;
  float direction_x;        // unit, where the light travels (sun, rect, disk)
  float direction_y;
  float direction_z;
  float half_u_x;           // rect, disk: tangent * width / 2
  float half_u_y;
  float half_u_z;
  float half_v_x;           // rect, disk: bitangent * height / 2
  float half_v_y;
  float half_v_z;
};

struct VisMesh {
  uint vertex_offset;       // first vertex in positions / normals
  uint index_offset;        // first element in indices (3 per triangle)
  uint permutation_offset;  // first element in permutation (one per triangle)
  uint flags;               // kVisMesh*
};

// Primary ray of pixel (x, y): direction = normalize(tx * axis_x + ty * axis_y - axis_z) with
// tx = tan_left + (x + 0.5) * tan_step_x, ty = tan_up - (y + 0.5) * tan_step_y (Camera::eye_ray).
struct VisPushConstants {
  float eye_x;  // eye position, scene-relative
  float eye_y;
  float eye_z;
  float tan_left;
  float axis_x_x;  // the eye's +X axis in the world (rotation only)
  float axis_x_y;
  float axis_x_z;
  float tan_up;
  float axis_y_x;  // the eye's +Y axis
  float axis_y_y;
  float axis_y_z;
  float tan_step_x;
  float axis_z_x;  // the eye's +Z axis (backward)
  float axis_z_y;
  float axis_z_z;
  float tan_step_y;
  uint width;
  uint height;
  uint light_count;
  uint active_lights;  // bit i: light i not culled for this view
  uint flags;          // kVisSkip*
  float ray_offset_scale;  // server/trace/include/trace/ray_offset.hpp: ray_offset_scale(scene bounds), a power of two
  float primary_near;      // primary rays start at this depth along the view axis (the client's near plane)
  uint soft_lights;        // bit i: light i has a level field (sampled over its extent); 0: one bit per light
  uint soft_initial_samples;  // SoftOptions::initial_samples (powers of two: the levels equal quantize()'s)
  uint soft_max_samples;      // SoftOptions::max_samples
};

#ifdef __cplusplus
static_assert(sizeof(VisMesh) == 16, "VisMesh must match the std430 array stride");
static_assert(sizeof(VisSoftLight) == 64, "VisSoftLight must match the std430 array stride");
static_assert(sizeof(VisPushConstants) == 104, "push constants must match the GLSL layout");
#endif

#endif  // DHR_VIS_INTERFACE_H
