// Internal to dhr_vk (used by context.cpp): probing physical devices for what DHR-XR needs,
// choosing one by preference, and building the device create info with its feature chain.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

#include "vk/context.hpp"

namespace dhr::vk::detail {

// Feature structs linked into one pNext chain. Holds pointers to itself: not copyable.
struct FeatureChain {
  VkPhysicalDeviceFeatures2 core{};
  VkPhysicalDeviceVulkan11Features v11{};
  VkPhysicalDeviceVulkan12Features v12{};
  VkPhysicalDeviceVulkan13Features v13{};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR acceleration_structure{};
  VkPhysicalDeviceRayTracingPipelineFeaturesKHR ray_tracing_pipeline{};
  VkPhysicalDeviceRayQueryFeaturesKHR ray_query{};
  // The Vulkan 1.2 features as their individual (promoted extension) structs, chained instead of v12
  // when split_vulkan12: an OpenXR runtime (Monado) appends its own TimelineSemaphoreFeatures unless that
  // struct type is already in the chain, and next to VkPhysicalDeviceVulkan12Features that is invalid
  // (VUID-VkDeviceCreateInfo-pNext-02830).
  VkPhysicalDeviceBufferDeviceAddressFeatures buffer_device_address{};
  VkPhysicalDeviceTimelineSemaphoreFeatures timeline_semaphore{};
  VkPhysicalDeviceScalarBlockLayoutFeatures scalar_block_layout{};
  VkPhysicalDeviceDescriptorIndexingFeatures descriptor_indexing{};
  VkPhysicalDeviceHostQueryResetFeatures host_query_reset{};

  FeatureChain() = default;
  FeatureChain(const FeatureChain&) = delete;
  FeatureChain& operator=(const FeatureChain&) = delete;

  // Sets sType on every struct and chains 1.1/1.2/1.3 always (1.2 as the individual structs when
  // split_vulkan12), the ray-tracing structs on request (a struct of an extension the device lacks must
  // not be chained).
  void link(bool with_ray_tracing, bool with_ray_query, bool split_vulkan12 = false);
};

// What one physical device offers, and why it cannot be used (if it cannot).
struct DeviceProbe {
  VkPhysicalDevice handle = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties{};
  std::vector<std::string> extensions;
  uint32_t queue_family = UINT32_MAX;
  uint32_t timestamp_valid_bits = 0;
  std::string unusable_reason;  // empty: meets the base requirements (Vulkan 1.3, queue, features)
  std::string ray_tracing_missing;  // empty: ray-tracing pipeline usable
  bool ray_query = false;
  FeatureChain supported;

  bool has_extension(const char* name) const;
  bool is_cpu() const { return properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
  std::string name() const { return properties.deviceName; }
};

void probe_physical_device(VkPhysicalDevice device, DeviceProbe& out);

// Chooses by preference among the instance's devices; throws std::runtime_error with a one-line
// message naming what is missing and how to get it.
VkPhysicalDevice select_physical_device(VkInstance instance, DevicePreference preference,
                                        bool require_ray_tracing);

// Device create info with everything it points to. Holds pointers to itself: not copyable.
struct DevicePlan {
  FeatureChain enabled;
  std::vector<std::string> extension_names;
  std::vector<const char*> extensions;
  float queue_priority = 1.0f;
  VkDeviceQueueCreateInfo queue{};
  VkDeviceCreateInfo info{};

  DevicePlan() = default;
  DevicePlan(const DevicePlan&) = delete;
  DevicePlan& operator=(const DevicePlan&) = delete;
};

// Fills out_plan for the probed device. Throws when an extra extension is unsupported.
void plan_device(const DeviceProbe& probe, bool enable_ray_tracing,
                 const std::vector<std::string>& extra_extensions, DevicePlan& out_plan);

// DeviceInfo of the probed device; ray-tracing flags say what is enabled.
DeviceInfo describe_device(const DeviceProbe& probe, bool ray_tracing_enabled, bool ray_query_enabled);

std::string version_string(uint32_t version);

}  // namespace dhr::vk::detail
