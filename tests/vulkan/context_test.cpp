// Context creation, device selection and its error messages, submit_and_wait, external-create hooks.
#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>

#include "vk/handle.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::vk {
namespace {

using test::gpu_requested;
using test::ScopedEnv;

bool has_name(const char* const* names, uint32_t count, const char* wanted) {
  for (uint32_t i = 0; i < count; ++i) {
    if (std::strcmp(names[i], wanted) == 0) return true;
  }
  return false;
}

std::string create_error(const ContextOptions& options) {
  try {
    Context::create(options);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

using ContextTest = test::VulkanTest;
using RayTracingContextTest = test::RayTracingTest;

TEST_F(RayTracingContextTest, ReportsLavapipeWithRayTracing) {
  const DeviceInfo& info = ctx().info();
  EXPECT_GE(info.api_version, VK_API_VERSION_1_3);
  EXPECT_TRUE(info.ray_tracing.enabled());
  EXPECT_GT(info.ray_tracing.shader_group_handle_size, 0u);
  EXPECT_GT(info.ray_tracing.shader_group_base_alignment, 0u);
  EXPECT_GE(info.ray_tracing.max_ray_recursion_depth, 1u);
  EXPECT_NE(ctx().rt().cmd_trace_rays, nullptr);
  EXPECT_NE(ctx().rt().create_acceleration_structure, nullptr);
  const std::string json = ctx().describe_json();
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.back(), '}');
  EXPECT_NE(json.find("\"ray_tracing\":{\"acceleration_structure\":true,\"pipeline\":true"), std::string::npos) << json;
  if (gpu_requested()) GTEST_SKIP() << "DHR_VK_DEVICE=gpu: lavapipe-specific checks skipped";
  EXPECT_TRUE(info.is_cpu);
  EXPECT_NE(info.name.find("llvmpipe"), std::string::npos) << info.name;
  EXPECT_NE(info.driver_name.find("llvmpipe"), std::string::npos) << info.driver_name;
  EXPECT_TRUE(info.ray_tracing.ray_query);  // lavapipe 25 has VK_KHR_ray_query
  EXPECT_TRUE(info.timestamps_supported);
  EXPECT_NE(json.find("llvmpipe"), std::string::npos) << json;
}

TEST_F(ContextTest, WithoutRayTracingLoadsNoRayTracingEntryPoints) {
  EXPECT_FALSE(ctx().info().ray_tracing.enabled());
  EXPECT_EQ(ctx().rt().cmd_trace_rays, nullptr);
  EXPECT_NE(ctx().queue(), VK_NULL_HANDLE);
  EXPECT_TRUE(ctx().validation_enabled());
  EXPECT_EQ(ctx().validation_error_count(), 0u);
}

TEST_F(ContextTest, SubmitAndWaitPropagatesExceptionsAndStaysUsable) {
  EXPECT_THROW(ctx().submit_and_wait([](VkCommandBuffer) { throw std::runtime_error("recording failed"); }),
               std::runtime_error);
  int recorded = 0;
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    EXPECT_NE(cmd, VK_NULL_HANDLE);
    ++recorded;
  });
  EXPECT_EQ(recorded, 1);
}

// A submit from inside a recording would wait for the lock its own thread holds: it throws instead, and the
// context stays usable (an EyePipeline once built a pass inside a recording and hung).
TEST_F(ContextTest, SubmittingFromInsideARecordingThrowsInsteadOfHanging) {
  bool inner_threw = false;
  ctx().submit_and_wait([&](VkCommandBuffer) {
    try {
      ctx().submit_and_wait([](VkCommandBuffer) {});
    } catch (const std::logic_error&) {
      inner_threw = true;
    }
    VkSubmitInfo2 submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO_2;
    EXPECT_THROW(ctx().submit(submit, VK_NULL_HANDLE), std::logic_error);
  });
  EXPECT_TRUE(inner_threw);
  int recorded = 0;
  ctx().submit_and_wait([&](VkCommandBuffer) { ++recorded; });
  EXPECT_EQ(recorded, 1);
}

TEST_F(ContextTest, SubmitSignalsFence) {
  VkFenceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  VkFence raw = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateFence(ctx().device(), &info, nullptr, &raw), VK_SUCCESS);
  const Fence fence(ctx().device(), raw);
  VkSubmitInfo2 submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO_2;
  ASSERT_EQ(ctx().submit(submit, fence.get()), VK_SUCCESS);
  EXPECT_EQ(vkWaitForFences(ctx().device(), 1, &raw, VK_TRUE, UINT64_MAX), VK_SUCCESS);
}

TEST_F(ContextTest, FindMemoryTypeFailsClearly) {
  EXPECT_NO_THROW(ctx().find_memory_type(~0u, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT));
  try {
    ctx().find_memory_type(0u, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no Vulkan memory type"), std::string::npos) << e.what();
  }
}

TEST(ContextErrors, GpuPreferenceOnGpuLessMachineFailsClearly) {
  ScopedEnv env("DHR_VK_DEVICE", "gpu");  // the environment overrides ContextOptions::device
  ContextOptions options;
  options.device = DevicePreference::kGpu;
  std::string message;
  try {
    const auto context = Context::create(options);
    if (!context->info().is_cpu) GTEST_SKIP() << "a GPU is present: " << context->info().name;
    FAIL() << "a CPU device was accepted for DevicePreference::kGpu";
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("gpu"), std::string::npos) << message;
  EXPECT_NE(message.find("no GPU Vulkan device"), std::string::npos) << message;
  EXPECT_NE(message.find("DHR_VK_DEVICE=lavapipe"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
}

TEST(ContextErrors, NoDriverFailsClearly) {
  ScopedEnv drivers("VK_DRIVER_FILES", "/nonexistent/dhr_no_such_icd.json");
  ScopedEnv device("DHR_VK_DEVICE", nullptr);
  const std::string message = create_error(ContextOptions{});
  EXPECT_NE(message.find("no Vulkan driver found"), std::string::npos) << message;
  EXPECT_NE(message.find("mesa-vulkan-drivers"), std::string::npos) << message;
}

TEST(ContextErrors, BadEnvironmentPreferenceFailsClearly) {
  ScopedEnv env("DHR_VK_DEVICE", "quantum");
  const std::string message = create_error(ContextOptions{});
  EXPECT_NE(message.find("DHR_VK_DEVICE"), std::string::npos) << message;
  EXPECT_NE(message.find("quantum"), std::string::npos) << message;
}

TEST(ContextErrors, ParseDevicePreference) {
  EXPECT_EQ(parse_device_preference("auto"), DevicePreference::kAuto);
  EXPECT_EQ(parse_device_preference("gpu"), DevicePreference::kGpu);
  EXPECT_EQ(parse_device_preference("lavapipe"), DevicePreference::kLavapipe);
  EXPECT_EQ(parse_device_preference("cpu"), DevicePreference::kLavapipe);
  EXPECT_THROW(parse_device_preference("GPU0"), std::invalid_argument);
  EXPECT_THROW(parse_device_preference(""), std::invalid_argument);
}

// The OpenXR path: the hooks receive the create infos the context built and create the handles.
TEST(ContextExternal, HooksReceiveTheCreateInfos) {
  const uint32_t errors_before = process_validation_error_count();
  bool instance_hook = false;
  bool pick_hook = false;
  bool device_hook = false;
  ExternalCreate external;
  external.create_instance = [&](const VkInstanceCreateInfo& info) {
    instance_hook = true;
    EXPECT_NE(info.pApplicationInfo, nullptr);
    EXPECT_EQ(info.pApplicationInfo->apiVersion, VK_API_VERSION_1_3);
    EXPECT_TRUE(has_name(info.ppEnabledLayerNames, info.enabledLayerCount, "VK_LAYER_KHRONOS_validation"));
    VkInstance instance = VK_NULL_HANDLE;
    EXPECT_EQ(vkCreateInstance(&info, nullptr, &instance), VK_SUCCESS);
    return instance;
  };
  external.pick_physical_device = [&](VkInstance instance) {
    pick_hook = true;
    uint32_t count = 1;
    VkPhysicalDevice device = VK_NULL_HANDLE;
    const VkResult result = vkEnumeratePhysicalDevices(instance, &count, &device);
    EXPECT_TRUE(result == VK_SUCCESS || result == VK_INCOMPLETE);
    return device;
  };
  external.create_device = [&](VkPhysicalDevice physical, const VkDeviceCreateInfo& info) {
    device_hook = true;
    EXPECT_TRUE(has_name(info.ppEnabledExtensionNames, info.enabledExtensionCount,
                         VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME));
    EXPECT_NE(info.pNext, nullptr);  // the feature chain
    VkDevice device = VK_NULL_HANDLE;
    EXPECT_EQ(vkCreateDevice(physical, &info, nullptr, &device), VK_SUCCESS);
    return device;
  };
  ContextOptions options;
  options.validation = true;
  options.require_ray_tracing = true;
  {
    const auto context = Context::create(options, &external);
    EXPECT_TRUE(instance_hook && pick_hook && device_hook);
    EXPECT_TRUE(context->info().ray_tracing.enabled());
    context->submit_and_wait([](VkCommandBuffer) {});
  }
  EXPECT_EQ(process_validation_error_count() - errors_before, 0u);
}

}  // namespace
}  // namespace dhr::vk
