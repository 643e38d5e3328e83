#include "xr/swapchain.hpp"

#include <algorithm>
#include <array>

#include "log/log.hpp"
#include "xr/xr_check.hpp"
#include "xr/xr_struct.hpp"

namespace dhr::xr {

std::optional<VkFormat> choose_color_format(std::span<const int64_t> runtime_formats,
                                            ColorEncoding preferred) {
  constexpr std::array<VkFormat, 2> kSrgb = {VK_FORMAT_R8G8B8A8_SRGB, VK_FORMAT_B8G8R8A8_SRGB};
  constexpr std::array<VkFormat, 2> kUnorm = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_UNORM};
  const auto& first = preferred == ColorEncoding::kSrgb ? kSrgb : kUnorm;
  const auto& second = preferred == ColorEncoding::kSrgb ? kUnorm : kSrgb;
  for (const auto* group : {&first, &second}) {
    for (VkFormat format : *group) {
      if (std::find(runtime_formats.begin(), runtime_formats.end(), static_cast<int64_t>(format)) !=
          runtime_formats.end()) {
        return format;
      }
    }
  }
  return std::nullopt;
}

std::vector<int64_t> swapchain_formats(XrSession session) {
  uint32_t count = 0;
  DHR_XR_CHECK(xrEnumerateSwapchainFormats(session, 0, &count, nullptr));
  std::vector<int64_t> formats(count);
  DHR_XR_CHECK(xrEnumerateSwapchainFormats(session, count, &count, formats.data()));
  formats.resize(count);
  return formats;
}

Swapchain::Swapchain(XrSession session, const SwapchainDesc& desc) : desc_(desc) {
  auto create_info = make_xr<XrSwapchainCreateInfo>(XR_TYPE_SWAPCHAIN_CREATE_INFO);
  create_info.usageFlags = desc.usage;
  create_info.format = static_cast<int64_t>(desc.format);
  create_info.sampleCount = desc.sample_count;
  create_info.width = desc.width;
  create_info.height = desc.height;
  create_info.faceCount = 1;
  create_info.arraySize = 1;
  create_info.mipCount = 1;
  DHR_XR_CHECK(xrCreateSwapchain(session, &create_info, &swapchain_));

  try {
    uint32_t count = 0;
    DHR_XR_CHECK(xrEnumerateSwapchainImages(swapchain_, 0, &count, nullptr));
    std::vector<XrSwapchainImageVulkan2KHR> images(
        count, make_xr<XrSwapchainImageVulkan2KHR>(XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR));
    DHR_XR_CHECK(xrEnumerateSwapchainImages(
        swapchain_, count, &count, reinterpret_cast<XrSwapchainImageBaseHeader*>(images.data())));
    images_.reserve(count);
    for (uint32_t i = 0; i < count; ++i) images_.push_back(images[i].image);
  } catch (...) {
    xrDestroySwapchain(swapchain_);
    throw;
  }
  dhr::log::debug("openxr: swapchain %ux%u format %d, %zu images", desc.width, desc.height,
                  static_cast<int>(desc.format), images_.size());
}

Swapchain::~Swapchain() {
  if (swapchain_ != XR_NULL_HANDLE) xrDestroySwapchain(swapchain_);
}

XrResult Swapchain::acquire(uint32_t* out_index) {
  auto acquire_info = make_xr<XrSwapchainImageAcquireInfo>(XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO);
  DHR_XR_TRY(xrAcquireSwapchainImage(swapchain_, &acquire_info, out_index));
  if (*out_index >= images_.size()) return XR_ERROR_VALIDATION_FAILURE;  // a runtime bug
  return XR_SUCCESS;
}

XrResult Swapchain::wait(XrDuration timeout) {
  auto wait_info = make_xr<XrSwapchainImageWaitInfo>(XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO);
  wait_info.timeout = timeout;
  const XrResult result = xrWaitSwapchainImage(swapchain_, &wait_info);
  DHR_XR_TRY(result);
  return result;
}

XrResult Swapchain::release() {
  auto release_info = make_xr<XrSwapchainImageReleaseInfo>(XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO);
  DHR_XR_TRY(xrReleaseSwapchainImage(swapchain_, &release_info));
  return XR_SUCCESS;
}

}  // namespace dhr::xr
