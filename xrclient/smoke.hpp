// dhr-xrclient --smoke: open the headset, run N frames that clear each eye to a colour that
// changes over time (different per eye), record session states and eye poses, shut down cleanly.
#pragma once
#include <cstdint>

#include "smoke_report.hpp"
#include "vk/context.hpp"
#include "xr/swapchain.hpp"

namespace dhr {

struct SmokeOptions {
  uint32_t frames = 300;  // frames presented (with a projection layer) before asking to exit
  double timeout_s = 60.0;  // wall-clock cap of the frame phase; then the session is asked to exit
  dhr::vk::DevicePreference device = dhr::vk::DevicePreference::kAuto;
  xr::ColorEncoding color_encoding = xr::ColorEncoding::kSrgb;
};

// Throws (one-line message) when the headset cannot be opened: no runtime, no HMD, no Vulkan
// device, session refused. Everything after that ends up in the report's "exit" field.
SmokeReport run_smoke(const SmokeOptions& options);

}  // namespace dhr
