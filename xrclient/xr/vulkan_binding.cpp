#include "xr/vulkan_binding.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "log/log.hpp"
#include "vk/check.hpp"
#include "xr/instance.hpp"
#include "xr/xr_check.hpp"
#include "xr/xr_struct.hpp"

namespace dhr::xr {

namespace {

// major.minor packed so that plain integer comparison orders versions.
uint64_t major_minor_of_xr(XrVersion version) {
  return (XR_VERSION_MAJOR(version) << 16) | XR_VERSION_MINOR(version);
}

uint64_t major_minor_of_vk(uint32_t version) {
  return (static_cast<uint64_t>(VK_API_VERSION_MAJOR(version)) << 16) | VK_API_VERSION_MINOR(version);
}

std::string xr_version_text(XrVersion version) {
  char text[32];
  std::snprintf(text, sizeof text, "%u.%u", static_cast<unsigned>(XR_VERSION_MAJOR(version)),
                static_cast<unsigned>(XR_VERSION_MINOR(version)));
  return text;
}

// The runtime chooses the device; an explicit preference turns a mismatch into a clear error
// instead of, say, a real headset silently composited on the CPU.
void check_preference(VkPhysicalDevice device, dhr::vk::DevicePreference preference) {
  if (preference == dhr::vk::DevicePreference::kAuto) return;
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(device, &properties);
  const bool is_cpu = properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  if (preference == dhr::vk::DevicePreference::kGpu && is_cpu) {
    throw std::runtime_error(std::string("the OpenXR runtime uses the CPU Vulkan device '") +
                             properties.deviceName +
                             "' but a GPU was requested (--vk-device gpu / DHR_VK_DEVICE=gpu); "
                             "unset VK_DRIVER_FILES so the runtime can see the GPU");
  }
  if (preference == dhr::vk::DevicePreference::kLavapipe && !is_cpu) {
    throw std::runtime_error(std::string("the OpenXR runtime uses the GPU '") + properties.deviceName +
                             "' but lavapipe was requested (--vk-device lavapipe); set "
                             "VK_DRIVER_FILES to lavapipe's ICD (runtime-config/with-monado does)");
  }
}

dhr::vk::DevicePreference effective_preference(dhr::vk::DevicePreference requested) {
  // Same rule as dhr::vk::Context: the environment variable wins over the option.
  const char* env = std::getenv("DHR_VK_DEVICE");
  if (env == nullptr || *env == '\0') return requested;
  try {
    return dhr::vk::parse_device_preference(env);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("DHR_VK_DEVICE: ") + e.what());
  }
}

}  // namespace

bool vulkan_version_supported(uint32_t vk_api_version, const VulkanRequirements& requirements) {
  return major_minor_of_vk(vk_api_version) >= major_minor_of_xr(requirements.min_api_version);
}

VulkanBinding::VulkanBinding(const Instance& instance, XrSystemId system)
    : instance_(instance.handle()), system_(system) {
  auto get_requirements = instance.proc_as<PFN_xrGetVulkanGraphicsRequirements2KHR>(
      "xrGetVulkanGraphicsRequirements2KHR");
  create_instance_ = instance.proc_as<PFN_xrCreateVulkanInstanceKHR>("xrCreateVulkanInstanceKHR");
  get_device_ = instance.proc_as<PFN_xrGetVulkanGraphicsDevice2KHR>("xrGetVulkanGraphicsDevice2KHR");
  create_device_ = instance.proc_as<PFN_xrCreateVulkanDeviceKHR>("xrCreateVulkanDeviceKHR");

  auto graphics_requirements = make_xr<XrGraphicsRequirementsVulkan2KHR>(XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR);
  DHR_XR_CHECK(get_requirements(instance_, system_, &graphics_requirements));
  requirements_.min_api_version = graphics_requirements.minApiVersionSupported;
  requirements_.max_api_version = graphics_requirements.maxApiVersionSupported;
  dhr::log::info("openxr: runtime supports Vulkan %s .. %s",
                 xr_version_text(requirements_.min_api_version).c_str(),
                 xr_version_text(requirements_.max_api_version).c_str());
}

dhr::vk::ExternalCreate VulkanBinding::external_create(dhr::vk::DevicePreference preference) const {
  dhr::vk::ExternalCreate hooks;
  hooks.create_instance = [this](const VkInstanceCreateInfo& info) {
    const uint32_t api = info.pApplicationInfo != nullptr ? info.pApplicationInfo->apiVersion
                                                          : VK_API_VERSION_1_0;
    if (!vulkan_version_supported(api, requirements_)) {
      throw std::runtime_error("the OpenXR runtime needs Vulkan >= " +
                               xr_version_text(requirements_.min_api_version) +
                               ", the context asks for an older version");
    }
    if (major_minor_of_vk(api) > major_minor_of_xr(requirements_.max_api_version)) {
      // maxApiVersionSupported is the newest version the runtime was tested with, not a limit.
      dhr::log::warn("openxr: Vulkan %u.%u is newer than the runtime's tested %s",
                     VK_API_VERSION_MAJOR(api), VK_API_VERSION_MINOR(api),
                     xr_version_text(requirements_.max_api_version).c_str());
    }
    auto create_info = make_xr<XrVulkanInstanceCreateInfoKHR>(XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR);
    create_info.systemId = system_;
    create_info.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
    create_info.vulkanCreateInfo = &info;
    VkInstance vk_instance = VK_NULL_HANDLE;
    VkResult vk_result = VK_SUCCESS;
    DHR_XR_CHECK(create_instance_(instance_, &create_info, &vk_instance, &vk_result));
    DHR_VK_CHECK(vk_result);
    return vk_instance;
  };
  hooks.pick_physical_device = [this, preference](VkInstance vk_instance) {
    auto get_info = make_xr<XrVulkanGraphicsDeviceGetInfoKHR>(XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR);
    get_info.systemId = system_;
    get_info.vulkanInstance = vk_instance;
    VkPhysicalDevice physical_device = VK_NULL_HANDLE;
    DHR_XR_CHECK(get_device_(instance_, &get_info, &physical_device));
    if (physical_device == VK_NULL_HANDLE) {
      throw std::runtime_error("the OpenXR runtime reports no Vulkan device for the headset");
    }
    check_preference(physical_device, preference);
    return physical_device;
  };
  hooks.create_device = [this](VkPhysicalDevice physical_device, const VkDeviceCreateInfo& info) {
    auto create_info = make_xr<XrVulkanDeviceCreateInfoKHR>(XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR);
    create_info.systemId = system_;
    create_info.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
    create_info.vulkanPhysicalDevice = physical_device;
    create_info.vulkanCreateInfo = &info;
    VkDevice device = VK_NULL_HANDLE;
    VkResult vk_result = VK_SUCCESS;
    DHR_XR_CHECK(create_device_(instance_, &create_info, &device, &vk_result));
    DHR_VK_CHECK(vk_result);
    return device;
  };
  return hooks;
}

std::unique_ptr<dhr::vk::Context> VulkanBinding::create_context(
    const dhr::vk::ContextOptions& options) const {
  const dhr::vk::ExternalCreate hooks = external_create(effective_preference(options.device));
  std::unique_ptr<dhr::vk::Context> context = dhr::vk::Context::create(options, &hooks);
  dhr::log::info("openxr: Vulkan device %s (%s)", context->info().name.c_str(),
                 context->info().driver_name.c_str());
  return context;
}

XrGraphicsBindingVulkan2KHR VulkanBinding::graphics_binding(const dhr::vk::Context& context) const {
  auto binding = make_xr<XrGraphicsBindingVulkan2KHR>(XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR);
  binding.instance = context.instance();
  binding.physicalDevice = context.physical_device();
  binding.device = context.device();
  binding.queueFamilyIndex = context.queue_family();
  binding.queueIndex = 0;
  return binding;
}

}  // namespace dhr::xr
