#include "xr/instance.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "log/log.hpp"
#include "xr/openxr_vulkan.hpp"
#include "xr/xr_check.hpp"
#include "xr/xr_struct.hpp"

namespace dhr::xr {

namespace {

constexpr const char* kNoRuntimeHint =
    "no OpenXR runtime found (set XR_RUNTIME_JSON or run scripts/setup for Monado)";

[[noreturn]] void throw_no_runtime(XrResult result) {
  std::string message = kNoRuntimeHint;
  message += ": loader returned " + result_name(result);
  if (const char* manifest = std::getenv("XR_RUNTIME_JSON")) {
    message += ", XR_RUNTIME_JSON=";
    message += manifest;
  }
  throw RuntimeUnavailable(message);
}

XRAPI_ATTR XrBool32 XRAPI_CALL debug_callback(XrDebugUtilsMessageSeverityFlagsEXT severity,
                                              XrDebugUtilsMessageTypeFlagsEXT /*types*/,
                                              const XrDebugUtilsMessengerCallbackDataEXT* data,
                                              void* /*user*/) {
  const char* function = data->functionName != nullptr ? data->functionName : "?";
  const char* message = data->message != nullptr ? data->message : "";
  if ((severity & XR_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) != 0) {
    dhr::log::error("openxr runtime: %s: %s", function, message);
  } else if ((severity & XR_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) != 0) {
    dhr::log::warn("openxr runtime: %s: %s", function, message);
  } else {
    dhr::log::debug("openxr runtime: %s: %s", function, message);
  }
  return XR_FALSE;  // never abort the call that triggered the message
}

}  // namespace

std::string RuntimeInfo::describe() const {
  char version_text[48];
  std::snprintf(version_text, sizeof version_text, "%u.%u.%u",
                static_cast<unsigned>(XR_VERSION_MAJOR(version)),
                static_cast<unsigned>(XR_VERSION_MINOR(version)),
                static_cast<unsigned>(XR_VERSION_PATCH(version)));
  return name + " " + version_text;
}

std::vector<std::string> available_instance_extensions() {
  uint32_t count = 0;
  XrResult result = xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr);
  // The first loader call is where a missing or broken runtime shows up, whatever the code.
  if (XR_FAILED(result)) throw_no_runtime(result);
  std::vector<XrExtensionProperties> properties(
      count, make_xr<XrExtensionProperties>(XR_TYPE_EXTENSION_PROPERTIES));
  result = xrEnumerateInstanceExtensionProperties(nullptr, count, &count, properties.data());
  if (XR_FAILED(result)) throw_no_runtime(result);
  std::vector<std::string> names;
  names.reserve(count);
  for (uint32_t i = 0; i < count; ++i) names.emplace_back(properties[i].extensionName);
  return names;
}

std::unique_ptr<Instance> Instance::create(const InstanceOptions& options) {
  const std::vector<std::string> available = available_instance_extensions();
  auto has = [&](const char* name) {
    return std::find(available.begin(), available.end(), name) != available.end();
  };
  if (!has(XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME)) {
    throw std::runtime_error("the OpenXR runtime does not offer " XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME
                             " (DHR-XR renders with Vulkan)");
  }

  std::unique_ptr<Instance> self(new Instance());
  self->enabled_extensions_.emplace_back(XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME);
  const bool debug_utils = options.debug_utils && has(XR_EXT_DEBUG_UTILS_EXTENSION_NAME);
  if (debug_utils) self->enabled_extensions_.emplace_back(XR_EXT_DEBUG_UTILS_EXTENSION_NAME);
  std::vector<const char*> extension_names;
  for (const std::string& name : self->enabled_extensions_) extension_names.push_back(name.c_str());

  auto create_info = make_xr<XrInstanceCreateInfo>(XR_TYPE_INSTANCE_CREATE_INFO);
  std::snprintf(create_info.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "%s",
                options.app_name.c_str());
  create_info.applicationInfo.applicationVersion = options.app_version;
  std::snprintf(create_info.applicationInfo.engineName, XR_MAX_ENGINE_NAME_SIZE, "%s", "dhr-xr");
  create_info.applicationInfo.engineVersion = 1;
  create_info.applicationInfo.apiVersion = XR_CURRENT_API_VERSION;
  create_info.enabledExtensionCount = static_cast<uint32_t>(extension_names.size());
  create_info.enabledExtensionNames = extension_names.data();
  const XrResult result = xrCreateInstance(&create_info, &self->instance_);
  if (result == XR_ERROR_RUNTIME_UNAVAILABLE || result == XR_ERROR_RUNTIME_FAILURE) {
    throw_no_runtime(result);
  }
  DHR_XR_CHECK(result);

  auto properties = make_xr<XrInstanceProperties>(XR_TYPE_INSTANCE_PROPERTIES);
  DHR_XR_CHECK(xrGetInstanceProperties(self->instance_, &properties));
  self->runtime_.name = properties.runtimeName;
  self->runtime_.version = properties.runtimeVersion;
  dhr::log::info("openxr: runtime %s", self->runtime_.describe().c_str());

  if (debug_utils) {
    auto create_messenger =
        self->proc_as<PFN_xrCreateDebugUtilsMessengerEXT>("xrCreateDebugUtilsMessengerEXT");
    auto messenger_info = make_xr<XrDebugUtilsMessengerCreateInfoEXT>(XR_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
    messenger_info.messageSeverities = XR_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT |
                                       XR_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                       XR_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT;
    messenger_info.messageTypes = XR_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                  XR_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                  XR_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                                  XR_DEBUG_UTILS_MESSAGE_TYPE_CONFORMANCE_BIT_EXT;
    messenger_info.userCallback = debug_callback;
    const XrResult messenger_result =
        create_messenger(self->instance_, &messenger_info, &self->messenger_);
    // Debug output is a convenience: its absence must not stop the client.
    if (XR_FAILED(messenger_result)) {
      dhr::log::warn("openxr: debug utils messenger unavailable (%s)",
                     result_name(messenger_result).c_str());
      self->messenger_ = XR_NULL_HANDLE;
    }
  }
  return self;
}

Instance::~Instance() {
  if (messenger_ != XR_NULL_HANDLE) {
    PFN_xrVoidFunction destroy = nullptr;
    if (XR_SUCCEEDED(xrGetInstanceProcAddr(instance_, "xrDestroyDebugUtilsMessengerEXT", &destroy)) &&
        destroy != nullptr) {
      reinterpret_cast<PFN_xrDestroyDebugUtilsMessengerEXT>(destroy)(messenger_);
    }
  }
  if (instance_ != XR_NULL_HANDLE) xrDestroyInstance(instance_);
}

bool Instance::extension_enabled(const std::string& name) const {
  return std::find(enabled_extensions_.begin(), enabled_extensions_.end(), name) !=
         enabled_extensions_.end();
}

PFN_xrVoidFunction Instance::proc(const char* name) const {
  PFN_xrVoidFunction function = nullptr;
  const XrResult result = xrGetInstanceProcAddr(instance_, name, &function);
  if (XR_FAILED(result) || function == nullptr) {
    throw_xr_error(XR_FAILED(result) ? result : XR_ERROR_FUNCTION_UNSUPPORTED, name);
  }
  return function;
}

}  // namespace dhr::xr
