// Where a frame's two shaded eye images go (swapchain, PNG files, a test's readback). The coordinator calls
// record() inside the frame's command buffer, after both eyes' passes, and after_submit() once that command
// buffer is submitted. The images are EyePipeline::output(): R8G8B8A8_UNORM, sRGB-encoded bytes, GENERAL.
#pragma once
#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>

namespace dhr::vk {
class Image;
}

namespace dhr::client {

using EyeImages = std::array<vk::Image*, 2>;

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void record(VkCommandBuffer /*cmd*/, uint64_t /*frame*/, const EyeImages& /*eyes*/) {}
  virtual void after_submit(uint64_t /*frame*/, const EyeImages& /*eyes*/) {}
};

}  // namespace dhr::client
