// Small helpers shared by the client's passes.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>

#include "vk/barriers.hpp"
#include "vk/handle.hpp"
#include "vk/image.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

// Nearest-neighbour, clamp-to-edge sampler for texelFetch-style reads of G-buffer images.
vk::Sampler create_nearest_sampler(VkDevice device);

// An attachment of dynamic rendering that is cleared to `clear` and stored; a null view discards the shader's
// writes to it (the pipeline's format for it must then be VK_FORMAT_UNDEFINED).
VkRenderingAttachmentInfo cleared_attachment(VkImageView view, VkImageLayout layout, VkClearValue clear);
// Begins dynamic rendering over (0, 0, width, height), one layer; `depth` may be null.
void begin_rendering(VkCommandBuffer cmd, uint32_t width, uint32_t height,
                     std::span<const VkRenderingAttachmentInfo> colour, const VkRenderingAttachmentInfo* depth);
// The same over `area` (what a tiling rasterizer loads and stores: a pass drawing into part of an atlas names it).
void begin_rendering(VkCommandBuffer cmd, const VkRect2D& area, std::span<const VkRenderingAttachmentInfo> colour,
                     const VkRenderingAttachmentInfo* depth);

// Throws std::runtime_error naming `pass` unless the device has subgroup arithmetic in compute shaders (the
// warp's and the forward pass's counts sum per subgroup).
void require_subgroup_arithmetic(const vk::Context& context, const char* pass);

// One binding of a compute pass's descriptor set (one descriptor, compute stage).
struct ComputeBinding {
  uint32_t binding;
  VkDescriptorType type;
};

// The fixed objects of a client compute pass: a nearest sampler, its descriptor set layout, a pipeline layout
// with one push-constant range, the compute pipeline of one client shader, and a pool sized for `slots`
// descriptor sets of that layout.
struct ComputePassCore {
  vk::Sampler sampler;
  vk::DescriptorSetLayout set_layout;
  vk::PipelineLayout layout;
  vk::Pipeline pipeline;
  vk::DescriptorPool pool;

  // `shader`: the module's name in dhr_shaders_client (e.g. "shading.comp"). Throws on Vulkan errors.
  static ComputePassCore create(VkDevice device, std::span<const ComputeBinding> bindings, uint32_t push_size,
                                const char* shader, uint32_t slots);
  VkDescriptorSet allocate_set(VkDevice device) const;
  // Binds the pipeline and `set`, pushes the constants and dispatches group_size x group_size groups over extent.
  void dispatch(VkCommandBuffer cmd, VkDescriptorSet set, const void* push, uint32_t push_size, uint32_t width,
                uint32_t height, uint32_t group_size) const;
};

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
