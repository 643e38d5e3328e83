// Copies the shaded eye images into the OpenXR swapchain images acquired for this frame (raw
// vkCmdCopyImage: the bytes are already sRGB-encoded, see docs/client.md, Shading). The images arrive and
// leave in COLOR_ATTACHMENT_OPTIMAL, as the runtime hands them over.
#pragma once
#include <array>

#include "frame/frame_sink.hpp"
#include "xr/frame_loop.hpp"

namespace dhr::client {

class SwapchainSink final : public FrameSink {
 public:
  // The targets of the frame about to be rendered (FrameLoop's render callback).
  void set_targets(const std::array<xr::EyeTarget, xr::kEyeCount>& targets) { targets_ = targets; }
  void record(VkCommandBuffer cmd, uint64_t frame, const EyeImages& eyes) override;

 private:
  std::array<xr::EyeTarget, xr::kEyeCount> targets_{};
};

}  // namespace dhr::client
