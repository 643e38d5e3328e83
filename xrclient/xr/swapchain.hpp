// One OpenXR swapchain (one per eye) and its Vulkan images.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "xr/openxr_vulkan.hpp"

namespace dhr::xr {

enum class ColorEncoding { kSrgb, kUnorm };

// Picks an 8-bit RGBA (or BGRA) colour format from the runtime's list, preferring the requested
// encoding and falling back to the other one. std::nullopt when the list has none of them.
std::optional<VkFormat> choose_color_format(std::span<const int64_t> runtime_formats,
                                            ColorEncoding preferred);

// The formats the runtime can allocate swapchains in, in its order of preference.
std::vector<int64_t> swapchain_formats(XrSession session);

struct SwapchainDesc {
  uint32_t width = 0;
  uint32_t height = 0;
  VkFormat format = VK_FORMAT_UNDEFINED;
  uint32_t sample_count = 1;
  // Colour attachment for rendering, transfer destination for clears and copies.
  XrSwapchainUsageFlags usage =
      XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
};

class Swapchain {
 public:
  Swapchain(XrSession session, const SwapchainDesc& desc);  // throws XrError
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  XrSwapchain handle() const { return swapchain_; }
  const SwapchainDesc& desc() const { return desc_; }
  const std::vector<VkImage>& images() const { return images_; }

  // Per-frame calls return the XrResult. wait() returns XR_TIMEOUT_EXPIRED (a success code)
  // when the image did not become available within timeout; the image stays acquired.
  XrResult acquire(uint32_t* out_index);
  XrResult wait(XrDuration timeout);
  XrResult release();

 private:
  XrSwapchain swapchain_ = XR_NULL_HANDLE;
  SwapchainDesc desc_;
  std::vector<VkImage> images_;
};

}  // namespace dhr::xr
