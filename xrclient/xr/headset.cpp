#include "xr/headset.hpp"

#include <stdexcept>

#include "log/log.hpp"
#include "xr/xr_check.hpp"

namespace dhr::xr {

std::unique_ptr<Headset> Headset::open(const HeadsetOptions& options) {
  std::unique_ptr<Headset> self(new Headset());
  self->instance_ = Instance::create(options.instance);
  self->system_ = query_system(self->instance_->handle());
  self->binding_ = std::make_unique<VulkanBinding>(*self->instance_, self->system_.id);
  self->vulkan_ = self->binding_->create_context(options.vulkan);
  self->session_ = std::make_unique<Session>(self->instance_->handle(), self->system_.id,
                                             self->binding_->graphics_binding(*self->vulkan_));
  self->spaces_ = std::make_unique<ReferenceSpaces>(self->session_->handle());

  const std::vector<int64_t> formats = swapchain_formats(self->session_->handle());
  const std::optional<VkFormat> format = choose_color_format(formats, options.color_encoding);
  if (!format) {
    throw std::runtime_error("the OpenXR runtime offers no 8-bit RGBA/BGRA swapchain format");
  }
  std::array<Swapchain*, kEyeCount> swapchain_pointers{};
  for (uint32_t eye = 0; eye < kEyeCount; ++eye) {
    SwapchainDesc desc;
    desc.width = self->system_.views[eye].recommendedImageRectWidth;
    desc.height = self->system_.views[eye].recommendedImageRectHeight;
    desc.format = *format;
    desc.usage = options.swapchain_usage;
    self->swapchains_[eye] = std::make_unique<Swapchain>(self->session_->handle(), desc);
    swapchain_pointers[eye] = self->swapchains_[eye].get();
  }
  dhr::log::info("openxr: swapchains %ux%u + %ux%u, VkFormat %d, %zu images each",
                 self->swapchains_[0]->desc().width, self->swapchains_[0]->desc().height,
                 self->swapchains_[1]->desc().width, self->swapchains_[1]->desc().height,
                 static_cast<int>(*format), self->swapchains_[0]->images().size());
  self->frame_loop_ = std::make_unique<FrameLoop>(*self->session_, *self->spaces_,
                                                  swapchain_pointers, self->system_.blend_mode,
                                                  options.frame_loop);
  return self;
}

Headset::~Headset() {
  // The runtime may still use the images on the app's queue; let that finish before the
  // swapchains, the session and the device go away.
  if (vulkan_ != nullptr) vkDeviceWaitIdle(vulkan_->device());
}

}  // namespace dhr::xr
