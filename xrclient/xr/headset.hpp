// Everything needed to render to a headset, created in the required order and destroyed in
// reverse: OpenXR instance -> HMD system -> Vulkan context (through XR_KHR_vulkan_enable2) ->
// session -> reference spaces -> one swapchain per eye -> frame loop.
#pragma once
#include <array>
#include <memory>

#include "vk/context.hpp"
#include "xr/frame_loop.hpp"
#include "xr/instance.hpp"
#include "xr/session.hpp"
#include "xr/spaces.hpp"
#include "xr/swapchain.hpp"
#include "xr/system.hpp"
#include "xr/vulkan_binding.hpp"

namespace dhr::xr {

struct HeadsetOptions {
  InstanceOptions instance;
  dhr::vk::ContextOptions vulkan;
  ColorEncoding color_encoding = ColorEncoding::kSrgb;
  XrSwapchainUsageFlags swapchain_usage = SwapchainDesc{}.usage;
  FrameLoopOptions frame_loop;
};

class Headset {
 public:
  // Throws RuntimeUnavailable (no runtime), SessionRefused, std::runtime_error (no HMD, no
  // Vulkan device, no usable swapchain format) or XrError, each with a one-line message.
  static std::unique_ptr<Headset> open(const HeadsetOptions& options);
  ~Headset();
  Headset(const Headset&) = delete;
  Headset& operator=(const Headset&) = delete;

  const Instance& instance() const { return *instance_; }
  const SystemInfo& system() const { return system_; }
  dhr::vk::Context& vulkan() const { return *vulkan_; }
  Session& session() const { return *session_; }
  const ReferenceSpaces& spaces() const { return *spaces_; }
  const Swapchain& swapchain(uint32_t eye) const { return *swapchains_.at(eye); }
  FrameLoop& frame_loop() const { return *frame_loop_; }

 private:
  Headset() = default;
  // Declaration order is destruction order in reverse: the frame loop first, the instance last.
  std::unique_ptr<Instance> instance_;
  SystemInfo system_;
  std::unique_ptr<VulkanBinding> binding_;
  std::unique_ptr<dhr::vk::Context> vulkan_;
  std::unique_ptr<Session> session_;
  std::unique_ptr<ReferenceSpaces> spaces_;
  std::array<std::unique_ptr<Swapchain>, kEyeCount> swapchains_;
  std::unique_ptr<FrameLoop> frame_loop_;
};

}  // namespace dhr::xr
