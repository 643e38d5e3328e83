// Ray-tracing pipeline from raygen/miss/hit SPIR-V modules, with its shader binding table.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "vk/buffer.hpp"
#include "vk/handle.hpp"
#include "vk/spirv.hpp"

namespace dhr::vk {

class Context;

struct RayTracingHitGroup {
  const SpirvModule* closest_hit = nullptr;  // either may be null (not both)
  const SpirvModule* any_hit = nullptr;
};

struct RayTracingPipelineDesc {
  const SpirvModule* raygen = nullptr;        // required; entry point "main" for every stage
  std::vector<const SpirvModule*> miss;       // miss index i = traceRayEXT's missIndex
  std::vector<RayTracingHitGroup> hit_groups;  // triangle hit groups, SBT record offset i
  VkPipelineLayout layout = VK_NULL_HANDLE;
  uint32_t max_recursion_depth = 1;
};

class RayTracingPipeline {
 public:
  RayTracingPipeline() = default;
  // Needs a Context with ray tracing enabled; throws std::invalid_argument on a bad description.
  RayTracingPipeline(const Context& context, const RayTracingPipelineDesc& desc);

  VkPipeline pipeline() const { return pipeline_.get(); }
  VkPipelineLayout layout() const { return layout_; }
  const VkStridedDeviceAddressRegionKHR& raygen_region() const { return raygen_; }
  const VkStridedDeviceAddressRegionKHR& miss_region() const { return miss_; }
  const VkStridedDeviceAddressRegionKHR& hit_region() const { return hit_; }
  const VkStridedDeviceAddressRegionKHR& callable_region() const { return callable_; }
  explicit operator bool() const { return static_cast<bool>(pipeline_); }

  // Binds the pipeline and records vkCmdTraceRaysKHR over width x height x depth launch indices.
  // Descriptor sets and push constants are the caller's (bind them before or after this call's bind
  // point is set: they use VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR).
  void bind(VkCommandBuffer cmd) const;
  void trace(VkCommandBuffer cmd, uint32_t width, uint32_t height, uint32_t depth = 1) const;

 private:
  Pipeline pipeline_;
  Buffer sbt_;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  PFN_vkCmdTraceRaysKHR trace_fn_ = nullptr;
  VkStridedDeviceAddressRegionKHR raygen_{};
  VkStridedDeviceAddressRegionKHR miss_{};
  VkStridedDeviceAddressRegionKHR hit_{};
  VkStridedDeviceAddressRegionKHR callable_{};
};

}  // namespace dhr::vk
