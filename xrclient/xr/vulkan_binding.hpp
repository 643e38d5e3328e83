// XR_KHR_vulkan_enable2: the runtime creates the Vulkan instance and device (so it can add what
// its compositor needs) from the create infos dhr::vk::Context builds, and picks the physical
// device the headset is attached to.
#pragma once
#include <memory>

#include "vk/context.hpp"
#include "xr/openxr_vulkan.hpp"

namespace dhr::xr {

class Instance;

struct VulkanRequirements {
  XrVersion min_api_version = 0;  // Vulkan versions in XR_MAKE_VERSION form
  XrVersion max_api_version = 0;
};

class VulkanBinding {
 public:
  // Queries the runtime's Vulkan requirements (OpenXR requires this before session creation).
  VulkanBinding(const Instance& instance, XrSystemId system);

  const VulkanRequirements& requirements() const { return requirements_; }

  // Hooks for dhr::vk::Context::create that route instance, physical device and device creation
  // through xrCreateVulkanInstanceKHR / xrGetVulkanGraphicsDevice2KHR / xrCreateVulkanDeviceKHR.
  // They throw (XrError, dhr::vk::VulkanError, std::runtime_error) on failure and refer to this
  // object, which must outlive the create call. The runtime picks the physical device; the
  // preference only checks it (gpu: not a CPU device; lavapipe: a CPU device).
  dhr::vk::ExternalCreate external_create(dhr::vk::DevicePreference preference) const;

  // Creates the context through the hooks (options.device, overridden by DHR_VK_DEVICE as in
  // dhr::vk::Context). Throws with a one-line message when there is no usable Vulkan device.
  std::unique_ptr<dhr::vk::Context> create_context(const dhr::vk::ContextOptions& options) const;

  // The binding to chain into XrSessionCreateInfo (queue index 0 of the context's family).
  XrGraphicsBindingVulkan2KHR graphics_binding(const dhr::vk::Context& context) const;

 private:
  XrInstance instance_ = XR_NULL_HANDLE;
  XrSystemId system_ = XR_NULL_SYSTEM_ID;
  VulkanRequirements requirements_;
  PFN_xrCreateVulkanInstanceKHR create_instance_ = nullptr;
  PFN_xrGetVulkanGraphicsDevice2KHR get_device_ = nullptr;
  PFN_xrCreateVulkanDeviceKHR create_device_ = nullptr;
};

// Whether a Vulkan apiVersion (VK_MAKE_API_VERSION form) satisfies the requirements, comparing
// major.minor only as the extension specifies.
bool vulkan_version_supported(uint32_t vk_api_version, const VulkanRequirements& requirements);

}  // namespace dhr::xr
