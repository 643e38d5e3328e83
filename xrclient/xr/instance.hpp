// The OpenXR instance: loads the runtime (the loader finds it via XR_RUNTIME_JSON or the
// system's active_runtime.json), enables XR_KHR_vulkan_enable2 and, when the runtime has it,
// XR_EXT_debug_utils so runtime messages reach our log.
#pragma once
#include <openxr/openxr.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace dhr::xr {

// No runtime could be loaded (no manifest, a manifest naming a missing library, ...).
class RuntimeUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RuntimeInfo {
  std::string name;        // XrInstanceProperties::runtimeName
  XrVersion version = 0;   // XrInstanceProperties::runtimeVersion
  std::string describe() const;  // "Monado(XRT) ... 25.0.0"
};

struct InstanceOptions {
  std::string app_name = "dhr-xrclient";
  uint32_t app_version = 1;
  bool debug_utils = true;  // only when the runtime offers XR_EXT_debug_utils
};

class Instance {
 public:
  // Throws RuntimeUnavailable with "no OpenXR runtime found (...)" when no runtime loads, and
  // XrError when the runtime lacks XR_KHR_vulkan_enable2 or refuses the instance.
  static std::unique_ptr<Instance> create(const InstanceOptions& options = {});
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  XrInstance handle() const { return instance_; }
  const RuntimeInfo& runtime() const { return runtime_; }
  bool extension_enabled(const std::string& name) const;

  // xrGetInstanceProcAddr for extension functions; throws XrError when the runtime lacks it.
  PFN_xrVoidFunction proc(const char* name) const;
  template <typename Pfn>
  Pfn proc_as(const char* name) const {
    return reinterpret_cast<Pfn>(proc(name));
  }

 private:
  Instance() = default;
  XrInstance instance_ = XR_NULL_HANDLE;
  XrDebugUtilsMessengerEXT messenger_ = XR_NULL_HANDLE;
  RuntimeInfo runtime_;
  std::vector<std::string> enabled_extensions_;
};

// Instance extensions the runtime offers. Throws RuntimeUnavailable when no runtime loads.
std::vector<std::string> available_instance_extensions();

}  // namespace dhr::xr
