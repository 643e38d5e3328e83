// Vulkan context: instance, physical device, one device with one graphics+compute queue.
// Either creates everything itself (headless) or lets an external owner (OpenXR's
// XR_KHR_vulkan_enable2) create the instance and device from the create infos built here.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dhr::vk {

enum class DevicePreference {
  kAuto,      // a real GPU when present, lavapipe otherwise
  kGpu,       // a real (non-CPU) GPU, error when none
  kLavapipe,  // the CPU implementation (llvmpipe/lavapipe), error when absent
};

// Parses "auto" | "gpu" | "lavapipe" (also "cpu"); throws std::invalid_argument otherwise.
DevicePreference parse_device_preference(const std::string& text);

struct ContextOptions {
  std::string app_name = "dhr-xr";
  // Overridden by the environment variable DHR_VK_DEVICE (auto|gpu|lavapipe) when set.
  DevicePreference device = DevicePreference::kAuto;
  // Enable VK_KHR_acceleration_structure + ray_tracing_pipeline (+ ray_query where present).
  bool want_ray_tracing = false;
  // Fail with a clear error when ray tracing is unavailable (implies want_ray_tracing).
  bool require_ray_tracing = false;
  // Enable VK_LAYER_KHRONOS_validation with a debug messenger that counts errors.
  // Overridden by DHR_VK_VALIDATION=0/1 when set. Missing layer: a warning, not an error.
  bool validation = false;
  std::vector<std::string> extra_instance_extensions;
  std::vector<std::string> extra_device_extensions;
};

// Flags: what is enabled on the context's device. Sizes/alignments: the device's properties (filled
// whenever it has the ray-tracing extensions, enabled or not).
struct RayTracingSupport {
  bool acceleration_structure = false;
  bool ray_tracing_pipeline = false;
  bool ray_query = false;
  uint32_t shader_group_handle_size = 0;
  uint32_t shader_group_handle_alignment = 0;
  uint32_t shader_group_base_alignment = 0;
  uint32_t max_ray_recursion_depth = 0;
  uint32_t min_acceleration_structure_scratch_offset_alignment = 0;
  bool enabled() const { return acceleration_structure && ray_tracing_pipeline; }
};

struct DeviceInfo {
  std::string name;          // VkPhysicalDeviceProperties::deviceName
  std::string driver_name;   // VkPhysicalDeviceDriverProperties::driverName
  std::string driver_info;   // VkPhysicalDeviceDriverProperties::driverInfo
  uint32_t api_version = 0;  // device's reported version
  uint32_t vendor_id = 0;
  uint32_t device_id = 0;
  bool is_cpu = false;       // VK_PHYSICAL_DEVICE_TYPE_CPU (lavapipe)
  bool is_discrete_gpu = false;  // VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU
  float timestamp_period_ns = 0.0f;
  bool timestamps_supported = false;
  uint32_t timestamp_valid_bits = 0;  // of the context's queue family (0: no timestamps)
  RayTracingSupport ray_tracing;
};

// Validation errors seen by every Context of this process so far, including those reported while a
// Context is destroyed (leaked handles), which its own validation_error_count() can no longer show.
uint32_t process_validation_error_count();

// Lets an external owner (the OpenXR runtime) create the instance and the device. Each hook
// receives the create info the context built (extensions, layers, feature chain) and returns
// the handle the owner created. The context still owns and destroys what is returned.
struct ExternalCreate {
  std::function<VkInstance(const VkInstanceCreateInfo&)> create_instance;
  std::function<VkPhysicalDevice(VkInstance)> pick_physical_device;
  std::function<VkDevice(VkPhysicalDevice, const VkDeviceCreateInfo&)> create_device;
};

// Ray-tracing entry points, loaded with vkGetDeviceProcAddr when ray tracing is enabled.
struct RayTracingDispatch {
  PFN_vkCreateAccelerationStructureKHR create_acceleration_structure = nullptr;
  PFN_vkDestroyAccelerationStructureKHR destroy_acceleration_structure = nullptr;
  PFN_vkGetAccelerationStructureBuildSizesKHR get_acceleration_structure_build_sizes = nullptr;
  PFN_vkCmdBuildAccelerationStructuresKHR cmd_build_acceleration_structures = nullptr;
  PFN_vkGetAccelerationStructureDeviceAddressKHR get_acceleration_structure_device_address = nullptr;
  PFN_vkCmdWriteAccelerationStructuresPropertiesKHR cmd_write_acceleration_structures_properties = nullptr;
  PFN_vkCmdCopyAccelerationStructureKHR cmd_copy_acceleration_structure = nullptr;
  PFN_vkCreateRayTracingPipelinesKHR create_ray_tracing_pipelines = nullptr;
  PFN_vkGetRayTracingShaderGroupHandlesKHR get_ray_tracing_shader_group_handles = nullptr;
  PFN_vkCmdTraceRaysKHR cmd_trace_rays = nullptr;
};

class Context {
 public:
  // Throws std::runtime_error with a one-line message naming what is missing and how to get it
  // (no Vulkan driver, no matching device, no ray tracing when required).
  static std::unique_ptr<Context> create(const ContextOptions& options,
                                         const ExternalCreate* external = nullptr);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_device_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  const DeviceInfo& info() const { return info_; }
  const RayTracingDispatch& rt() const { return rt_; }

  // Validation messages of severity error seen so far (0 when validation is off).
  uint32_t validation_error_count() const;
  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }

  // Records and submits one command buffer on the queue and waits for it (setup/readback path).
  // Thread-safe with respect to itself and submit(). Called (or submit() called) from inside `record` on the
  // same thread, it throws std::logic_error instead of waiting for itself.
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const;
  // vkQueueSubmit2 on the context's queue under the same lock as submit_and_wait (the queue needs
  // external synchronization); per-frame code uses this instead of calling vkQueueSubmit2 directly.
  VkResult submit(const VkSubmitInfo2& info, VkFence fence) const;

  // Index of the first memory type in type_bits having all of flags; throws std::runtime_error if none.
  uint32_t find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const;
  const VkPhysicalDeviceMemoryProperties& memory_properties() const;

  // One-line JSON object describing the device: name, driver, api version, ray tracing support.
  std::string describe_json() const;

 private:
  Context() = default;
  struct Impl;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool setup_pool_ = VK_NULL_HANDLE;
  DeviceInfo info_;
  RayTracingDispatch rt_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dhr::vk
