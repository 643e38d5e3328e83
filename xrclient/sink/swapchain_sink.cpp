#include "sink/swapchain_sink.hpp"

#include <algorithm>

#include "vk/barriers.hpp"
#include "vk/image.hpp"

namespace dhr::client {

void SwapchainSink::record(VkCommandBuffer cmd, uint64_t /*frame*/, const EyeImages& eyes) {
  for (uint32_t e = 0; e < xr::kEyeCount; ++e) {
    const xr::EyeTarget& target = targets_[e];
    if (target.image == VK_NULL_HANDLE || eyes[e] == nullptr) continue;
    vk::Image& source = *eyes[e];
    vk::image_barrier(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                      VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkImageCopy region{};
    region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.extent = {std::min(source.width(), target.extent.width), std::min(source.height(), target.extent.height),
                     1};
    vkCmdCopyImage(cmd, source.handle(), source.layout(), target.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                   &region);
    vk::image_barrier(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                      VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  }
}

}  // namespace dhr::client
