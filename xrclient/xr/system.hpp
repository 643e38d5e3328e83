// The headset: an HMD system with the PRIMARY_STEREO view configuration.
#pragma once
#include <openxr/openxr.h>

#include <array>
#include <string>

namespace dhr::xr {

inline constexpr uint32_t kEyeCount = 2;

struct SystemInfo {
  XrSystemId id = XR_NULL_SYSTEM_ID;
  std::string name;  // XrSystemProperties::systemName
  uint32_t vendor_id = 0;
  bool orientation_tracking = false;
  bool position_tracking = false;
  uint32_t max_layer_count = 0;
  XrEnvironmentBlendMode blend_mode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  // Per eye (left, right): recommended and maximum image sizes, sample counts.
  std::array<XrViewConfigurationView, kEyeCount> views{};
};

// Throws a one-line std::runtime_error when no HMD is connected or it has no stereo view
// configuration; XrError for other failures.
SystemInfo query_system(XrInstance instance);

}  // namespace dhr::xr
