#include "vk/context.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "log/log.hpp"
#include "vk/check.hpp"
#include "vk/device_select.hpp"

namespace dhr::vk {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr const char* kNoDriver =
    "no Vulkan driver found (install mesa-vulkan-drivers or a GPU driver; run scripts/setup)";

std::atomic<uint32_t> g_process_validation_errors{0};

VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT types,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data,
                                              void* user_data) {
  const char* message = (data != nullptr && data->pMessage != nullptr) ? data->pMessage : "(no message)";
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    // Only validation errors count: the loader also reports (harmless) driver-probing errors.
    if (types & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT) {
      static_cast<std::atomic<uint32_t>*>(user_data)->fetch_add(1, std::memory_order_relaxed);
      g_process_validation_errors.fetch_add(1, std::memory_order_relaxed);
    }
    log::error("Vulkan: %s", message);
  } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    log::warn("Vulkan: %s", message);
  } else {
    log::debug("Vulkan: %s", message);
  }
  return VK_FALSE;  // never abort the call that triggered the message
}

std::vector<std::string> instance_extensions(const char* layer) {
  uint32_t count = 0;
  if (vkEnumerateInstanceExtensionProperties(layer, &count, nullptr) < 0) return {};
  std::vector<VkExtensionProperties> props(count);
  if (vkEnumerateInstanceExtensionProperties(layer, &count, props.data()) < 0) return {};
  std::vector<std::string> names;
  for (uint32_t i = 0; i < count; ++i) names.emplace_back(props[i].extensionName);
  return names;
}

bool has_instance_layer(const char* name) {
  uint32_t count = 0;
  if (vkEnumerateInstanceLayerProperties(&count, nullptr) < 0) return false;
  std::vector<VkLayerProperties> props(count);
  if (vkEnumerateInstanceLayerProperties(&count, props.data()) < 0) return false;
  for (uint32_t i = 0; i < count; ++i) {
    if (std::strcmp(props[i].layerName, name) == 0) return true;
  }
  return false;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

template <typename Fn>
void load_device_function(VkDevice device, Fn& out_fn, const char* name) {
  out_fn = reinterpret_cast<Fn>(vkGetDeviceProcAddr(device, name));
  if (out_fn == nullptr) {
    throw std::runtime_error(std::string("the Vulkan driver does not provide ") + name +
                             " although its extension is enabled (update the driver)");
  }
}

void append_json_string(std::string& out, const std::string& text) {
  out += '"';
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
      out += escaped;
    } else {
      out += c;
    }
  }
  out += '"';
}

}  // namespace

uint32_t process_validation_error_count() {
  return g_process_validation_errors.load(std::memory_order_relaxed);
}

DevicePreference parse_device_preference(const std::string& text) {
  if (text == "auto") return DevicePreference::kAuto;
  if (text == "gpu") return DevicePreference::kGpu;
  if (text == "lavapipe" || text == "cpu") return DevicePreference::kLavapipe;
  throw std::invalid_argument("unknown Vulkan device preference '" + text + "' (expected auto, gpu or lavapipe)");
}

struct Context::Impl {
  std::atomic<uint32_t> validation_errors{0};
  std::mutex submit_mutex;  // the queue and setup_pool_ need external synchronization
  // The thread inside submit_and_wait's `record` callback: a submit from there would wait for itself.
  std::atomic<std::thread::id> recording_thread{};
  void check_not_recording(const char* what) const {
    if (recording_thread.load() == std::this_thread::get_id()) {
      throw std::logic_error(std::string("vk::Context::") + what +
                             " called from inside submit_and_wait's recording (it would deadlock)");
    }
  }
  VkPhysicalDeviceMemoryProperties memory{};
  PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger = nullptr;

  static void create_instance(Context& ctx, const ContextOptions& options, const ExternalCreate* external);
  static void create_device(Context& ctx, const ContextOptions& options, const ExternalCreate* external);
};

void Context::Impl::create_instance(Context& ctx, const ContextOptions& options, const ExternalCreate* external) {
  uint32_t loader_version = VK_API_VERSION_1_0;
  if (vkEnumerateInstanceVersion(&loader_version) < 0 || loader_version < VK_API_VERSION_1_3) {
    throw std::runtime_error("Vulkan loader " + detail::version_string(loader_version) +
                             " is too old (need 1.3: install libvulkan1 >= 1.3; run scripts/setup)");
  }
  const std::vector<std::string> available = instance_extensions(nullptr);
  std::vector<const char*> layers;
  std::vector<std::string> extension_names;
  bool debug_utils = false;
  if (options.validation) {
    if (has_instance_layer(kValidationLayer)) {
      layers.push_back(kValidationLayer);
      const std::vector<std::string> from_layer = instance_extensions(kValidationLayer);
      debug_utils = contains(available, VK_EXT_DEBUG_UTILS_EXTENSION_NAME) ||
                    contains(from_layer, VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    } else {
      log::warn("Vulkan validation requested but %s is not installed (apt-get install vulkan-validationlayers); "
                "continuing without it", kValidationLayer);
    }
  }
  if (debug_utils) extension_names.emplace_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  for (const std::string& name : options.extra_instance_extensions) {
    if (!contains(available, name) && !(debug_utils && name == VK_EXT_DEBUG_UTILS_EXTENSION_NAME)) {
      throw std::runtime_error("Vulkan instance extension " + name +
                               " is not available (install a loader/driver that provides it)");
    }
    if (!contains(extension_names, name)) extension_names.push_back(name);
  }
  std::vector<const char*> extensions;
  for (const std::string& name : extension_names) extensions.push_back(name.c_str());

  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = options.app_name.c_str();
  app.applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
  app.pEngineName = "dhr-xr";
  app.engineVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
  app.apiVersion = VK_API_VERSION_1_3;

  // Chained into the instance create info too, so messages of vkCreate/DestroyInstance are seen.
  VkDebugUtilsMessengerCreateInfoEXT messenger_info{};
  messenger_info.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
  messenger_info.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
  messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger_info.pfnUserCallback = debug_callback;
  messenger_info.pUserData = &ctx.impl_->validation_errors;

  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pNext = debug_utils ? &messenger_info : nullptr;
  info.pApplicationInfo = &app;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();

  if (external != nullptr && external->create_instance) {
    ctx.instance_ = external->create_instance(info);
    if (ctx.instance_ == VK_NULL_HANDLE) {
      throw std::runtime_error("the external owner (OpenXR runtime) failed to create the Vulkan instance");
    }
  } else {
    const VkResult result = vkCreateInstance(&info, nullptr, &ctx.instance_);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER) throw std::runtime_error(kNoDriver);
    DHR_VK_CHECK(result);
  }

  if (debug_utils) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(ctx.instance_, "vkCreateDebugUtilsMessengerEXT"));
    ctx.impl_->destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(ctx.instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (create != nullptr && ctx.impl_->destroy_messenger != nullptr) {
      DHR_VK_CHECK(create(ctx.instance_, &messenger_info, nullptr, &ctx.messenger_));
    }
  }
}

void Context::Impl::create_device(Context& ctx, const ContextOptions& options, const ExternalCreate* external) {
  const bool want_rt = options.want_ray_tracing || options.require_ray_tracing;
  if (external != nullptr && external->pick_physical_device) {
    ctx.physical_device_ = external->pick_physical_device(ctx.instance_);
    if (ctx.physical_device_ == VK_NULL_HANDLE) {
      throw std::runtime_error("the external owner (OpenXR runtime) returned no Vulkan physical device");
    }
  } else {
    ctx.physical_device_ = detail::select_physical_device(ctx.instance_, options.device, options.require_ray_tracing);
  }
  auto probe = std::make_unique<detail::DeviceProbe>();
  detail::probe_physical_device(ctx.physical_device_, *probe);
  if (external != nullptr && external->pick_physical_device &&
      ((options.device == DevicePreference::kGpu && probe->is_cpu()) ||
       (options.device == DevicePreference::kLavapipe && !probe->is_cpu()))) {
    log::warn("the external owner (OpenXR runtime) chose Vulkan device '%s', which does not match the device "
              "preference; using it anyway", probe->name().c_str());
  }
  const bool rt_available = probe->ray_tracing_missing.empty();
  if (want_rt && !rt_available && !options.require_ray_tracing) {
    log::warn("device '%s' has no ray tracing (missing %s); continuing without it", probe->name().c_str(),
              probe->ray_tracing_missing.c_str());
  }
  // require_ray_tracing without support makes plan_device throw the one-line explanation.
  const bool enable_rt = options.require_ray_tracing || (want_rt && rt_available);
  auto plan = std::make_unique<detail::DevicePlan>();
  detail::plan_device(*probe, enable_rt, options.extra_device_extensions, *plan);

  if (external != nullptr && external->create_device) {
    ctx.device_ = external->create_device(ctx.physical_device_, plan->info);
    if (ctx.device_ == VK_NULL_HANDLE) {
      throw std::runtime_error("the external owner (OpenXR runtime) failed to create the Vulkan device");
    }
  } else {
    DHR_VK_CHECK(vkCreateDevice(ctx.physical_device_, &plan->info, nullptr, &ctx.device_));
  }
  ctx.queue_family_ = probe->queue_family;
  vkGetDeviceQueue(ctx.device_, ctx.queue_family_, 0, &ctx.queue_);

  VkCommandPoolCreateInfo pool{};
  pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  pool.queueFamilyIndex = ctx.queue_family_;
  DHR_VK_CHECK(vkCreateCommandPool(ctx.device_, &pool, nullptr, &ctx.setup_pool_));

  const bool enable_rq = enable_rt && probe->ray_query;
  ctx.info_ = detail::describe_device(*probe, enable_rt, enable_rq);
  vkGetPhysicalDeviceMemoryProperties(ctx.physical_device_, &ctx.impl_->memory);
  if (enable_rt) {
    RayTracingDispatch& rt = ctx.rt_;
    const VkDevice d = ctx.device_;
    load_device_function(d, rt.create_acceleration_structure, "vkCreateAccelerationStructureKHR");
    load_device_function(d, rt.destroy_acceleration_structure, "vkDestroyAccelerationStructureKHR");
    load_device_function(d, rt.get_acceleration_structure_build_sizes, "vkGetAccelerationStructureBuildSizesKHR");
    load_device_function(d, rt.cmd_build_acceleration_structures, "vkCmdBuildAccelerationStructuresKHR");
    load_device_function(d, rt.get_acceleration_structure_device_address,
                         "vkGetAccelerationStructureDeviceAddressKHR");
    load_device_function(d, rt.cmd_write_acceleration_structures_properties,
                         "vkCmdWriteAccelerationStructuresPropertiesKHR");
    load_device_function(d, rt.cmd_copy_acceleration_structure, "vkCmdCopyAccelerationStructureKHR");
    load_device_function(d, rt.create_ray_tracing_pipelines, "vkCreateRayTracingPipelinesKHR");
    load_device_function(d, rt.get_ray_tracing_shader_group_handles, "vkGetRayTracingShaderGroupHandlesKHR");
    load_device_function(d, rt.cmd_trace_rays, "vkCmdTraceRaysKHR");
  }
  log::info("Vulkan device: %s (%s, %s), ray tracing %s%s", ctx.info_.name.c_str(), ctx.info_.driver_name.c_str(),
            ctx.info_.driver_info.c_str(), enable_rt ? "on" : "off", ctx.messenger_ ? ", validation on" : "");
}

std::unique_ptr<Context> Context::create(const ContextOptions& options_in, const ExternalCreate* external) {
  ContextOptions options = options_in;
  if (const char* env = std::getenv("DHR_VK_DEVICE"); env != nullptr && *env != '\0') {
    try {
      options.device = parse_device_preference(env);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(std::string("DHR_VK_DEVICE: ") + e.what());
    }
  }
  if (const char* env = std::getenv("DHR_VK_VALIDATION"); env != nullptr && *env != '\0') {
    options.validation = std::strcmp(env, "0") != 0;
  }
  // The destructor releases whatever was created before a failure.
  std::unique_ptr<Context> ctx(new Context());
  ctx->impl_ = std::make_unique<Impl>();
  Impl::create_instance(*ctx, options, external);
  Impl::create_device(*ctx, options, external);
  return ctx;
}

Context::~Context() {
  if (device_ != VK_NULL_HANDLE) {
    vkDeviceWaitIdle(device_);
    if (setup_pool_ != VK_NULL_HANDLE) vkDestroyCommandPool(device_, setup_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_ != VK_NULL_HANDLE) impl_->destroy_messenger(instance_, messenger_, nullptr);
  if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

uint32_t Context::validation_error_count() const {
  return impl_->validation_errors.load(std::memory_order_relaxed);
}

void Context::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const {
  impl_->check_not_recording("submit_and_wait");
  std::lock_guard lock(impl_->submit_mutex);
  VkCommandBufferAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  alloc.commandPool = setup_pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkAllocateCommandBuffers(device_, &alloc, &cmd));
  VkFence fence = VK_NULL_HANDLE;
  // Frees the command buffer and fence on every path, including a throwing `record`.
  struct Cleanup {
    VkDevice device;
    VkCommandPool pool;
    VkCommandBuffer& cmd;
    VkFence& fence;
    ~Cleanup() {
      if (fence != VK_NULL_HANDLE) vkDestroyFence(device, fence, nullptr);
      vkFreeCommandBuffers(device, pool, 1, &cmd);
    }
  } cleanup{device_, setup_pool_, cmd, fence};

  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  DHR_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
  {
    impl_->recording_thread.store(std::this_thread::get_id());
    struct Done {
      std::atomic<std::thread::id>& thread;
      ~Done() { thread.store(std::thread::id{}); }
    } done{impl_->recording_thread};
    record(cmd);
  }
  DHR_VK_CHECK(vkEndCommandBuffer(cmd));

  VkFenceCreateInfo fence_info{};
  fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  DHR_VK_CHECK(vkCreateFence(device_, &fence_info, nullptr, &fence));
  VkSubmitInfo submit_info{};
  submit_info.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  submit_info.commandBufferCount = 1;
  submit_info.pCommandBuffers = &cmd;
  DHR_VK_CHECK(vkQueueSubmit(queue_, 1, &submit_info, fence));
  DHR_VK_CHECK(vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX));
}

VkResult Context::submit(const VkSubmitInfo2& info, VkFence fence) const {
  impl_->check_not_recording("submit");
  std::lock_guard lock(impl_->submit_mutex);
  return vkQueueSubmit2(queue_, 1, &info, fence);
}

uint32_t Context::find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const {
  const VkPhysicalDeviceMemoryProperties& memory = impl_->memory;
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
    if ((type_bits & (1u << i)) != 0 && (memory.memoryTypes[i].propertyFlags & flags) == flags) return i;
  }
  char text[160];
  std::snprintf(text, sizeof text, "no Vulkan memory type with property flags 0x%x among type bits 0x%x on '%s'",
                static_cast<unsigned>(flags), static_cast<unsigned>(type_bits), info_.name.c_str());
  throw std::runtime_error(text);
}

const VkPhysicalDeviceMemoryProperties& Context::memory_properties() const { return impl_->memory; }

std::string Context::describe_json() const {
  const RayTracingSupport& rt = info_.ray_tracing;
  char numbers[512];
  std::string json = "{\"device\":";
  append_json_string(json, info_.name);
  json += ",\"driver\":";
  append_json_string(json, info_.driver_name);
  json += ",\"driver_info\":";
  append_json_string(json, info_.driver_info);
  json += ",\"api_version\":";
  append_json_string(json, detail::version_string(info_.api_version));
  std::snprintf(numbers, sizeof numbers,
                ",\"vendor_id\":%u,\"device_id\":%u,\"cpu\":%s,\"validation\":%s,"
                "\"timestamps\":%s,\"timestamp_period_ns\":%.6g,"
                "\"ray_tracing\":{\"acceleration_structure\":%s,\"pipeline\":%s,\"ray_query\":%s,"
                "\"shader_group_handle_size\":%u,\"max_ray_recursion_depth\":%u}}",
                info_.vendor_id, info_.device_id, info_.is_cpu ? "true" : "false",
                validation_enabled() ? "true" : "false", info_.timestamps_supported ? "true" : "false",
                static_cast<double>(info_.timestamp_period_ns), rt.acceleration_structure ? "true" : "false",
                rt.ray_tracing_pipeline ? "true" : "false", rt.ray_query ? "true" : "false",
                rt.shader_group_handle_size, rt.max_ray_recursion_depth);
  json += numbers;
  return json;
}

}  // namespace dhr::vk
