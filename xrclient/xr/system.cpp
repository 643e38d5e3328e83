#include "xr/system.hpp"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "log/log.hpp"
#include "xr/xr_check.hpp"
#include "xr/xr_struct.hpp"

namespace dhr::xr {

namespace {

constexpr XrViewConfigurationType kViewConfig = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;

XrEnvironmentBlendMode choose_blend_mode(XrInstance instance, XrSystemId system) {
  uint32_t count = 0;
  DHR_XR_CHECK(xrEnumerateEnvironmentBlendModes(instance, system, kViewConfig, 0, &count, nullptr));
  std::vector<XrEnvironmentBlendMode> modes(count);
  DHR_XR_CHECK(
      xrEnumerateEnvironmentBlendModes(instance, system, kViewConfig, count, &count, modes.data()));
  if (count == 0) throw std::runtime_error("the OpenXR runtime lists no environment blend mode");
  // Opaque is what a VR headset shows; otherwise take the runtime's preferred (first) mode.
  if (std::find(modes.begin(), modes.end(), XR_ENVIRONMENT_BLEND_MODE_OPAQUE) != modes.end()) {
    return XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  }
  return modes.front();
}

}  // namespace

SystemInfo query_system(XrInstance instance) {
  SystemInfo info;
  auto get_info = make_xr<XrSystemGetInfo>(XR_TYPE_SYSTEM_GET_INFO);
  get_info.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
  const XrResult result = xrGetSystem(instance, &get_info, &info.id);
  if (result == XR_ERROR_FORM_FACTOR_UNAVAILABLE || result == XR_ERROR_FORM_FACTOR_UNSUPPORTED) {
    throw std::runtime_error("no head-mounted display available from the OpenXR runtime (" +
                             result_name(result) + ")");
  }
  DHR_XR_CHECK(result);

  auto properties = make_xr<XrSystemProperties>(XR_TYPE_SYSTEM_PROPERTIES);
  DHR_XR_CHECK(xrGetSystemProperties(instance, info.id, &properties));
  info.name = properties.systemName;
  info.vendor_id = properties.vendorId;
  info.orientation_tracking = properties.trackingProperties.orientationTracking == XR_TRUE;
  info.position_tracking = properties.trackingProperties.positionTracking == XR_TRUE;
  info.max_layer_count = properties.graphicsProperties.maxLayerCount;

  uint32_t config_count = 0;
  DHR_XR_CHECK(xrEnumerateViewConfigurations(instance, info.id, 0, &config_count, nullptr));
  std::vector<XrViewConfigurationType> configs(config_count);
  DHR_XR_CHECK(
      xrEnumerateViewConfigurations(instance, info.id, config_count, &config_count, configs.data()));
  if (std::find(configs.begin(), configs.end(), kViewConfig) == configs.end()) {
    throw std::runtime_error("the headset '" + info.name +
                             "' has no PRIMARY_STEREO view configuration");
  }

  uint32_t view_count = 0;
  DHR_XR_CHECK(
      xrEnumerateViewConfigurationViews(instance, info.id, kViewConfig, 0, &view_count, nullptr));
  if (view_count != kEyeCount) {
    throw std::runtime_error("PRIMARY_STEREO reports " + std::to_string(view_count) +
                             " views, expected 2");
  }
  for (XrViewConfigurationView& view : info.views) view = make_xr<XrViewConfigurationView>(XR_TYPE_VIEW_CONFIGURATION_VIEW);
  DHR_XR_CHECK(xrEnumerateViewConfigurationViews(instance, info.id, kViewConfig, view_count,
                                                 &view_count, info.views.data()));
  info.blend_mode = choose_blend_mode(instance, info.id);

  dhr::log::info("openxr: system '%s' (vendor 0x%x), tracking orientation=%d position=%d, "
                 "recommended %ux%u / %ux%u per eye",
                 info.name.c_str(), info.vendor_id, info.orientation_tracking,
                 info.position_tracking, info.views[0].recommendedImageRectWidth,
                 info.views[0].recommendedImageRectHeight,
                 info.views[1].recommendedImageRectWidth,
                 info.views[1].recommendedImageRectHeight);
  return info;
}

}  // namespace dhr::xr
