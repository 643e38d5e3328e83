// The Vulkan ray-tracing backend of VisibilityTracer (GPUs; lavapipe for tests).
//
// Build: triangles of each SceneMesh::geometry sorted spatially (Morton order of centroids: lavapipe builds
// BVHs in input order), one compacted BLAS per geometry shared by its instances, a TLAS over the instances.
// Trace: one ray-tracing pipeline launch per eye (shaders/server/visibility.rgen): a primary ray per pixel
// centre, the surface point rebuilt from the scene-relative vertices, one terminate-on-first-hit shadow ray
// per light that can contribute (shaders/light_eval.h), a 32-bit mask per pixel packed to the buffer's width
// on readback. Same semantics as the Embree backend, which is the reference (see docs/server.md). trace_layout's
// soft fields: each soft light sampled over its extent in the shader with the Embree backend's sample points and
// rules (shaders/server/light_sampler.glsl; SoftOptions' defaults: 4 samples, 32 where they disagree, one scramble
// per light), its level Gray-coded into the field.
// Vulkan headers stay out of this file (server/trace/include/trace/vulkan/vulkan_tracer_internal.hpp has the GPU side).
#pragma once
#include "trace/visibility_tracer.hpp"

#include <memory>
#include <string>

namespace dhr::server {

// Internal knobs, measured in docs/server.md.
struct VulkanTracerConfig {
  // true: one BLAS per SceneMesh::geometry (and mirroring), instances share it through the TLAS;
  // false: one world-space BLAS per mesh (identity instances).
  bool instanced = true;
  bool morton_sort = true;  // sort each BLAS's triangles spatially before the build
  bool compact = true;      // compact every acceleration structure after its build
};

class VulkanTracer final : public VisibilityTracer {
 public:
  // Creates its own Vulkan context (TracerOptions::vk_device, vk_validation; DHR_VK_DEVICE and
  // DHR_VK_VALIDATION override them) and builds the acceleration structures. Throws std::runtime_error
  // with a one-line reason: no device with ray tracing, more than kMaxSlotLights lights (more than
  // kMaxLights share light slots, light_slots(), and refuse a scene with animation), a scene too large for
  // the device's storage-buffer range, a bad mesh (index out of range, non-finite vertex).
  VulkanTracer(const Scene& scene, const TracerOptions& options, const VulkanTracerConfig& config = {});
  ~VulkanTracer() override;
  VulkanTracer(const VulkanTracer&) = delete;
  VulkanTracer& operator=(const VulkanTracer&) = delete;

  TracerBackend backend() const override { return TracerBackend::kVulkan; }
  std::string device_description() const override;
  const AccelStats& accel_stats() const override;
  uint32_t light_count() const override;
  const LightSlots* light_slots() const override;
  // Concurrent calls are serialized (one queue, one set of frame buffers).
  void trace(const Camera& camera, VisibilityBuffer& out, TraceStats& out_stats) override;
  // Lights past `lights` are neither tested nor traced by the shader (push constant light_count).
  void trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out, TraceStats& out_stats) override;
  std::vector<bool> light_extents() const override;
  // Hard fields are trace_lights' bits; a soft field is the Gray code of the light's sampled visibility quantized
  // to 8 levels (the Embree backend's sampler in GLSL: within the bound of docs/server.md). Throws
  // std::invalid_argument for a layout of more lights than the scene has.
  void trace_layout(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out,
                    TraceStats& out_stats) override;

  // Moves the scene to scene time t (app-moved nodes where `overrides` puts them): moving meshes by their instance
  // transforms (one TLAS update; their BLASes, built at rest, stay) and their shading vertices, moved lights
  // re-uploaded (vulkan_scene_motion.cpp). Nothing for a scene without animation. Not concurrent with tracing.
  void set_scene_time(double t, const NodeOverrides* overrides = nullptr) override;
  bool moves() const override;
  double last_motion_update_ms() const override;
  const SceneAnimation* scene_animation() const override;

  const VulkanTracerConfig& config() const;
  // True on a CPU implementation (lavapipe).
  bool is_cpu_device() const;
  // Validation-layer errors reported by this tracer's context so far (0 when validation is off).
  uint32_t validation_error_count() const;

 private:
  void trace_fields(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out, TraceStats& out_stats);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::unique_ptr<VisibilityTracer> create_vulkan_tracer(const Scene& scene, const TracerOptions& options,
                                                       const VulkanTracerConfig& config = {});

}  // namespace dhr::server
