// The device feature chain survives an OpenXR runtime that edits it: Monado's xrCreateVulkanDeviceKHR
// prepends its own VkPhysicalDeviceTimelineSemaphoreFeatures unless that struct type is already chained,
// which next to VkPhysicalDeviceVulkan12Features is invalid (VUID-VkDeviceCreateInfo-pNext-02830).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "vk/buffer.hpp"
#include "vk/handle.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::vk {
namespace {

const VkBaseInStructure* find_in_chain(const void* next, VkStructureType type) {
  for (auto* s = static_cast<const VkBaseInStructure*>(next); s != nullptr; s = s->pNext)
    if (s->sType == type) return s;
  return nullptr;
}

TEST(ContextOpenXrChain, MonadoStyleDeviceCreationIsValid) {
  const uint32_t errors_before = process_validation_error_count();
  std::vector<VkStructureType> chained;
  ExternalCreate external;
  external.create_instance = [](const VkInstanceCreateInfo& info) {
    VkInstance instance = VK_NULL_HANDLE;
    EXPECT_EQ(vkCreateInstance(&info, nullptr, &instance), VK_SUCCESS);
    return instance;
  };
  external.pick_physical_device = [](VkInstance instance) {
    uint32_t count = 1;
    VkPhysicalDevice device = VK_NULL_HANDLE;
    const VkResult result = vkEnumeratePhysicalDevices(instance, &count, &device);
    EXPECT_TRUE(result == VK_SUCCESS || result == VK_INCOMPLETE);
    return device;
  };
  external.create_device = [&](VkPhysicalDevice physical, const VkDeviceCreateInfo& info) {
    for (auto* s = static_cast<const VkBaseInStructure*>(info.pNext); s != nullptr; s = s->pNext)
      chained.push_back(s->sType);
    // What Monado 25 does (src/xrt/state_trackers/oxr/oxr_vulkan.c): add timeline semaphores in front of
    // the application's chain unless the application chained that struct type itself.
    VkDeviceCreateInfo modified = info;
    VkPhysicalDeviceTimelineSemaphoreFeatures timeline{};
    timeline.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_TIMELINE_SEMAPHORE_FEATURES;
    timeline.timelineSemaphore = VK_TRUE;
    if (find_in_chain(info.pNext, VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_TIMELINE_SEMAPHORE_FEATURES) == nullptr) {
      timeline.pNext = const_cast<void*>(modified.pNext);
      modified.pNext = &timeline;
    }
    VkDevice device = VK_NULL_HANDLE;
    EXPECT_EQ(vkCreateDevice(physical, &modified, nullptr, &device), VK_SUCCESS);
    return device;
  };
  ContextOptions options;
  options.validation = true;
  options.require_ray_tracing = true;
  {
    const auto context = Context::create(options, &external);
    ASSERT_TRUE(context->validation_enabled());
    // The features the aggregate used to enable are still on: timeline semaphores, buffer device addresses.
    VkSemaphoreTypeCreateInfo type{};
    type.sType = VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO;
    type.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
    VkSemaphoreCreateInfo create{};
    create.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO;
    create.pNext = &type;
    VkSemaphore raw = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateSemaphore(context->device(), &create, nullptr, &raw), VK_SUCCESS);
    const Semaphore semaphore(context->device(), raw);
    const Buffer buffer(*context, 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                        VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    EXPECT_NE(buffer.address(), 0u);
  }
  auto has = [&](VkStructureType t) { return std::find(chained.begin(), chained.end(), t) != chained.end(); };
  EXPECT_FALSE(has(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES));
  EXPECT_TRUE(has(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_TIMELINE_SEMAPHORE_FEATURES));
  EXPECT_TRUE(has(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES));
  EXPECT_TRUE(has(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SCALAR_BLOCK_LAYOUT_FEATURES));
  EXPECT_EQ(process_validation_error_count() - errors_before, 0u) << "Vulkan validation errors (see log)";
}

}  // namespace
}  // namespace dhr::vk
