#include "vk/device_select.hpp"

#include <algorithm>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "vk/check.hpp"

namespace dhr::vk::detail {
namespace {

constexpr const char* kRayTracingHint =
    "Mesa >= 25 lavapipe from bookworm-backports, or an RT-capable GPU";

const char* type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

// Lower is better for DevicePreference::kAuto: real GPUs before virtual ones before the CPU.
int type_rank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_OTHER: return 3;
    default: return 4;
  }
}

struct RequiredFeature {
  const char* name;
  VkBool32 supported;
};

std::string device_list(const std::vector<std::unique_ptr<DeviceProbe>>& probes) {
  std::string text;
  for (const auto& p : probes) {
    if (!text.empty()) text += ", ";
    text += "'" + p->name() + "' (" + type_name(p->properties.deviceType) + ")";
  }
  return text.empty() ? "none" : text;
}

std::string ray_tracing_error(const DeviceProbe& probe) {
  return "device '" + probe.name() + "' has no ray tracing (need " + probe.ray_tracing_missing + ": " +
         kRayTracingHint + ")";
}

}  // namespace

void FeatureChain::link(bool with_ray_tracing, bool with_ray_query, bool split_vulkan12) {
  core.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  v11.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES;
  v12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  v13.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES;
  acceleration_structure.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR;
  ray_tracing_pipeline.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR;
  ray_query.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR;
  buffer_device_address.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES;
  timeline_semaphore.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_TIMELINE_SEMAPHORE_FEATURES;
  scalar_block_layout.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SCALAR_BLOCK_LAYOUT_FEATURES;
  descriptor_indexing.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DESCRIPTOR_INDEXING_FEATURES;
  host_query_reset.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_HOST_QUERY_RESET_FEATURES;
  core.pNext = &v11;
  if (split_vulkan12) {
    v11.pNext = &buffer_device_address;
    buffer_device_address.pNext = &timeline_semaphore;
    timeline_semaphore.pNext = &scalar_block_layout;
    scalar_block_layout.pNext = &descriptor_indexing;
    descriptor_indexing.pNext = &host_query_reset;
    host_query_reset.pNext = &v13;
  } else {
    v11.pNext = &v12;
    v12.pNext = &v13;
  }
  v13.pNext = nullptr;
  void** tail = &v13.pNext;
  if (with_ray_tracing) {
    *tail = &acceleration_structure;
    acceleration_structure.pNext = &ray_tracing_pipeline;
    ray_tracing_pipeline.pNext = nullptr;
    tail = &ray_tracing_pipeline.pNext;
  }
  if (with_ray_query) {
    *tail = &ray_query;
    ray_query.pNext = nullptr;
  }
}

bool DeviceProbe::has_extension(const char* name) const {
  return std::find(extensions.begin(), extensions.end(), name) != extensions.end();
}

std::string version_string(uint32_t version) {
  return std::to_string(VK_API_VERSION_MAJOR(version)) + "." + std::to_string(VK_API_VERSION_MINOR(version)) +
         "." + std::to_string(VK_API_VERSION_PATCH(version));
}

void probe_physical_device(VkPhysicalDevice device, DeviceProbe& out) {
  out.handle = device;
  vkGetPhysicalDeviceProperties(device, &out.properties);

  uint32_t count = 0;
  DHR_VK_CHECK(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> extensions(count);
  DHR_VK_CHECK(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data()));
  out.extensions.clear();
  for (uint32_t i = 0; i < count; ++i) out.extensions.emplace_back(extensions[i].extensionName);

  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  constexpr VkQueueFlags kNeeded = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
  for (uint32_t i = 0; i < count; ++i) {
    if ((families[i].queueFlags & kNeeded) == kNeeded) {
      out.queue_family = i;
      out.timestamp_valid_bits = families[i].timestampValidBits;
      break;
    }
  }

  const std::string quoted = "device '" + out.name() + "'";
  const bool rt_extensions = out.has_extension(VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME) &&
                             out.has_extension(VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME) &&
                             out.has_extension(VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME);
  const bool rq_extension = out.has_extension(VK_KHR_RAY_QUERY_EXTENSION_NAME);
  if (!out.has_extension(VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME)) {
    out.ray_tracing_missing = VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME;
  } else if (!out.has_extension(VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME)) {
    out.ray_tracing_missing = VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME;
  } else if (!out.has_extension(VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME)) {
    out.ray_tracing_missing = VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME;
  }

  if (out.properties.apiVersion < VK_API_VERSION_1_3) {
    // Vulkan 1.3 feature structs must not be queried on an older device.
    out.unusable_reason = quoted + " supports only Vulkan " + version_string(out.properties.apiVersion) +
                          " (need 1.3: update Mesa or the GPU driver; run scripts/setup)";
    if (out.ray_tracing_missing.empty()) out.ray_tracing_missing = "Vulkan 1.3";
    return;
  }
  out.supported.link(rt_extensions, rq_extension);
  vkGetPhysicalDeviceFeatures2(device, &out.supported.core);

  if (rt_extensions) {
    if (!out.supported.acceleration_structure.accelerationStructure) {
      out.ray_tracing_missing = "the accelerationStructure feature";
    } else if (!out.supported.ray_tracing_pipeline.rayTracingPipeline) {
      out.ray_tracing_missing = "the rayTracingPipeline feature";
    }
  }
  out.ray_query = rq_extension && out.supported.ray_query.rayQuery;

  if (out.queue_family == UINT32_MAX) {
    out.unusable_reason = quoted + " has no queue family with graphics and compute (use another device)";
    return;
  }
  const RequiredFeature required[] = {
      {"bufferDeviceAddress", out.supported.v12.bufferDeviceAddress},
      {"timelineSemaphore", out.supported.v12.timelineSemaphore},
      {"scalarBlockLayout", out.supported.v12.scalarBlockLayout},
      {"synchronization2", out.supported.v13.synchronization2},
      {"dynamicRendering", out.supported.v13.dynamicRendering},
  };
  for (const RequiredFeature& feature : required) {
    if (!feature.supported) {
      out.unusable_reason = quoted + " lacks the Vulkan feature " + feature.name +
                            " (update Mesa or the GPU driver; run scripts/setup)";
      return;
    }
  }
}

VkPhysicalDevice select_physical_device(VkInstance instance, DevicePreference preference,
                                        bool require_ray_tracing) {
  uint32_t count = 0;
  const VkResult result = vkEnumeratePhysicalDevices(instance, &count, nullptr);
  if (result == VK_ERROR_INITIALIZATION_FAILED || (result >= 0 && count == 0)) {
    throw std::runtime_error("no Vulkan driver found (install mesa-vulkan-drivers or a GPU driver; run scripts/setup)");
  }
  DHR_VK_CHECK(result);
  std::vector<VkPhysicalDevice> handles(count);
  DHR_VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, handles.data()));
  handles.resize(count);

  std::vector<std::unique_ptr<DeviceProbe>> all;
  for (VkPhysicalDevice handle : handles) {
    all.push_back(std::make_unique<DeviceProbe>());
    probe_physical_device(handle, *all.back());
  }
  // Stable: among equal ranks the loader's order wins (deterministic for a given machine).
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return type_rank(a->properties.deviceType) < type_rank(b->properties.deviceType);
  });

  std::vector<const DeviceProbe*> matching;
  for (const auto& p : all) {
    if (preference == DevicePreference::kGpu && p->is_cpu()) continue;
    if (preference == DevicePreference::kLavapipe && !p->is_cpu()) continue;
    matching.push_back(p.get());
  }
  if (matching.empty()) {
    if (preference == DevicePreference::kGpu) {
      throw std::runtime_error("device preference 'gpu' (DevicePreference::kGpu / DHR_VK_DEVICE=gpu): "
                               "no GPU Vulkan device found, only " +
                               device_list(all) +
                               " (install the GPU's Vulkan driver, or use DHR_VK_DEVICE=lavapipe)");
    }
    throw std::runtime_error("device preference 'lavapipe' (DevicePreference::kLavapipe / DHR_VK_DEVICE=lavapipe): "
                             "no CPU Vulkan device found, only " +
                             device_list(all) +
                             " (install mesa-vulkan-drivers from bookworm-backports; run scripts/setup)");
  }
  for (const DeviceProbe* p : matching) {
    if (p->unusable_reason.empty() && (!require_ray_tracing || p->ray_tracing_missing.empty())) {
      return p->handle;
    }
  }
  // None usable: explain why the best-ranked candidate was rejected.
  const DeviceProbe& best = *matching.front();
  if (!best.unusable_reason.empty()) throw std::runtime_error(best.unusable_reason);
  throw std::runtime_error(ray_tracing_error(best));
}

void plan_device(const DeviceProbe& probe, bool enable_ray_tracing,
                 const std::vector<std::string>& extra_extensions, DevicePlan& out_plan) {
  if (!probe.unusable_reason.empty()) throw std::runtime_error(probe.unusable_reason);
  if (enable_ray_tracing && !probe.ray_tracing_missing.empty()) {
    throw std::runtime_error(ray_tracing_error(probe));
  }
  const bool enable_ray_query = enable_ray_tracing && probe.ray_query;
  const FeatureChain& s = probe.supported;
  FeatureChain& e = out_plan.enabled;
  // The 1.2 features go in as individual structs on every path (see FeatureChain): an OpenXR runtime that
  // creates the device may add its own TimelineSemaphoreFeatures, which must not meet Vulkan12Features.
  e.link(enable_ray_tracing, enable_ray_query, /*split_vulkan12=*/true);

  // Optional features: enabled where supported, so later passes may use them without a new context.
  e.core.features.shaderInt64 = s.core.features.shaderInt64;
  e.core.features.samplerAnisotropy = s.core.features.samplerAnisotropy;
  e.core.features.fragmentStoresAndAtomics = s.core.features.fragmentStoresAndAtomics;
  e.core.features.shaderStorageImageReadWithoutFormat = s.core.features.shaderStorageImageReadWithoutFormat;
  e.core.features.shaderStorageImageWriteWithoutFormat = s.core.features.shaderStorageImageWriteWithoutFormat;
  e.v11.shaderDrawParameters = s.v11.shaderDrawParameters;
  // (Vulkan12Features::descriptorIndexing only reports that the set below is supported; it has no struct
  // of its own to enable.)
  e.descriptor_indexing.runtimeDescriptorArray = s.v12.runtimeDescriptorArray;
  e.descriptor_indexing.descriptorBindingPartiallyBound = s.v12.descriptorBindingPartiallyBound;
  e.descriptor_indexing.descriptorBindingVariableDescriptorCount = s.v12.descriptorBindingVariableDescriptorCount;
  e.descriptor_indexing.shaderSampledImageArrayNonUniformIndexing = s.v12.shaderSampledImageArrayNonUniformIndexing;
  e.descriptor_indexing.shaderStorageBufferArrayNonUniformIndexing = s.v12.shaderStorageBufferArrayNonUniformIndexing;
  e.host_query_reset.hostQueryReset = s.v12.hostQueryReset;
  e.v13.maintenance4 = s.v13.maintenance4;
  // Required (checked by probe_physical_device).
  e.buffer_device_address.bufferDeviceAddress = VK_TRUE;
  e.timeline_semaphore.timelineSemaphore = VK_TRUE;
  e.scalar_block_layout.scalarBlockLayout = VK_TRUE;
  e.v13.synchronization2 = VK_TRUE;
  e.v13.dynamicRendering = VK_TRUE;

  out_plan.extension_names.clear();
  if (enable_ray_tracing) {
    e.acceleration_structure.accelerationStructure = VK_TRUE;
    e.ray_tracing_pipeline.rayTracingPipeline = VK_TRUE;
    out_plan.extension_names = {VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
                                VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME,
                                VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME};
    if (enable_ray_query) {
      e.ray_query.rayQuery = VK_TRUE;
      out_plan.extension_names.emplace_back(VK_KHR_RAY_QUERY_EXTENSION_NAME);
    }
  }
  for (const std::string& name : extra_extensions) {
    if (!probe.has_extension(name.c_str())) {
      throw std::runtime_error("device extension " + name + " is not supported by '" + probe.name() +
                               "' (use another device or driver)");
    }
    if (std::find(out_plan.extension_names.begin(), out_plan.extension_names.end(), name) ==
        out_plan.extension_names.end()) {
      out_plan.extension_names.push_back(name);
    }
  }
  out_plan.extensions.clear();
  for (const std::string& name : out_plan.extension_names) out_plan.extensions.push_back(name.c_str());

  out_plan.queue = {};
  out_plan.queue.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  out_plan.queue.queueFamilyIndex = probe.queue_family;
  out_plan.queue.queueCount = 1;
  out_plan.queue.pQueuePriorities = &out_plan.queue_priority;

  out_plan.info = {};
  out_plan.info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  out_plan.info.pNext = &e.core;
  out_plan.info.queueCreateInfoCount = 1;
  out_plan.info.pQueueCreateInfos = &out_plan.queue;
  out_plan.info.enabledExtensionCount = static_cast<uint32_t>(out_plan.extensions.size());
  out_plan.info.ppEnabledExtensionNames = out_plan.extensions.data();
}

DeviceInfo describe_device(const DeviceProbe& probe, bool ray_tracing_enabled, bool ray_query_enabled) {
  DeviceInfo info;
  VkPhysicalDeviceDriverProperties driver{};
  driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
  VkPhysicalDeviceRayTracingPipelinePropertiesKHR rt{};
  rt.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_PROPERTIES_KHR;
  VkPhysicalDeviceAccelerationStructurePropertiesKHR as{};
  as.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR;
  VkPhysicalDeviceProperties2 props{};
  props.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  props.pNext = &driver;
  if (probe.has_extension(VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME) &&
      probe.has_extension(VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME)) {
    driver.pNext = &rt;
    rt.pNext = &as;
  }
  vkGetPhysicalDeviceProperties2(probe.handle, &props);

  info.name = props.properties.deviceName;
  info.driver_name = driver.driverName;
  info.driver_info = driver.driverInfo;
  info.api_version = props.properties.apiVersion;
  info.vendor_id = props.properties.vendorID;
  info.device_id = props.properties.deviceID;
  info.is_cpu = probe.is_cpu();
  info.is_discrete_gpu = probe.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
  info.timestamp_period_ns = props.properties.limits.timestampPeriod;
  info.timestamp_valid_bits = probe.timestamp_valid_bits;
  info.timestamps_supported = probe.timestamp_valid_bits > 0 && info.timestamp_period_ns > 0.0f;
  info.ray_tracing.acceleration_structure = ray_tracing_enabled;
  info.ray_tracing.ray_tracing_pipeline = ray_tracing_enabled;
  info.ray_tracing.ray_query = ray_query_enabled;
  info.ray_tracing.shader_group_handle_size = rt.shaderGroupHandleSize;
  info.ray_tracing.shader_group_handle_alignment = rt.shaderGroupHandleAlignment;
  info.ray_tracing.shader_group_base_alignment = rt.shaderGroupBaseAlignment;
  info.ray_tracing.max_ray_recursion_depth = rt.maxRayRecursionDepth;
  info.ray_tracing.min_acceleration_structure_scratch_offset_alignment =
      as.minAccelerationStructureScratchOffsetAlignment;
  return info;
}

}  // namespace dhr::vk::detail
