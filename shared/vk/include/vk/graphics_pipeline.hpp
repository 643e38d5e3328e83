// Graphics pipelines for dynamic rendering (Vulkan 1.3, no render pass objects): one builder call.
// Viewport and scissor are dynamic state (set them with set_viewport_and_scissor after binding).
#pragma once
#include <vulkan/vulkan.h>

#include <span>

#include "vk/handle.hpp"
#include "vk/spirv.hpp"

namespace dhr::vk {

struct GraphicsPipelineDesc {
  const SpirvModule* vertex = nullptr;    // required
  const SpirvModule* fragment = nullptr;  // optional (depth-only pipelines)
  std::span<const VkVertexInputBindingDescription> vertex_bindings;
  std::span<const VkVertexInputAttributeDescription> vertex_attributes;
  std::span<const VkFormat> color_formats;  // one per colour attachment, written without blending
  VkFormat depth_format = VK_FORMAT_UNDEFINED;
  bool depth_test = true;
  bool depth_write = true;
  VkCompareOp depth_compare = VK_COMPARE_OP_GREATER;  // reversed-Z
  VkCullModeFlags cull_mode = VK_CULL_MODE_NONE;
  VkFrontFace front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
};

// Throws std::invalid_argument when the vertex shader is missing, dhr::vk::VulkanError on failure.
Pipeline create_graphics_pipeline(VkDevice device, VkPipelineLayout layout, const GraphicsPipelineDesc& desc);

// Full-extent viewport (depth range 0..1) and scissor.
void set_viewport_and_scissor(VkCommandBuffer cmd, VkExtent2D extent);

}  // namespace dhr::vk
