// One-call synchronization2 barriers (vkCmdPipelineBarrier2 with a single barrier).
#pragma once
#include <vulkan/vulkan.h>

namespace dhr::vk {

// Global memory barrier.
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

// Image barrier over all mips/layers of `aspect`, with an optional layout change.
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout old_layout,
                   VkImageLayout new_layout, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                   VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

}  // namespace dhr::vk
