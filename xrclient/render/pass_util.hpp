// Small helpers shared by the client's passes.
#pragma once
#include <vulkan/vulkan.h>

#include "vk/barriers.hpp"
#include "vk/handle.hpp"
#include "vk/image.hpp"

namespace dhr::render {

// Nearest-neighbour, clamp-to-edge sampler for texelFetch-style reads of G-buffer images.
vk::Sampler create_nearest_sampler(VkDevice device);

// Moves an image that is about to be fully overwritten into `layout`, discarding its contents (old layout
// UNDEFINED) but still waiting for every earlier use of it (previous frames' readers).
inline void discard_to_layout(VkCommandBuffer cmd, vk::Image& image, VkImageLayout layout,
                              VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
  vk::image_barrier(cmd, image.handle(), image.aspect() & ~VkImageAspectFlags{VK_IMAGE_ASPECT_STENCIL_BIT},
                    VK_IMAGE_LAYOUT_UNDEFINED, layout, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE,
                    dst_stage, dst_access);
  image.set_layout(layout);
}

// Ensures an image is in `layout` for shader access; a no-op barrier when it already is, so a pass can be
// recorded on inputs produced earlier in the same command buffer.
inline void ensure_layout(VkCommandBuffer cmd, vk::Image& image, VkImageLayout layout) {
  if (image.layout() != layout) image.transition(cmd, layout);
}

}  // namespace dhr::render
