#include "render/pass_util.hpp"

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "dhr_shaders_client.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace dhr::render {

VkRenderingAttachmentInfo cleared_attachment(VkImageView view, VkImageLayout layout, VkClearValue clear) {
  VkRenderingAttachmentInfo a{};
  a.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
  a.imageView = view;
  a.imageLayout = layout;
  a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  a.clearValue = clear;
  return a;
}

void begin_rendering(VkCommandBuffer cmd, uint32_t width, uint32_t height,
                     std::span<const VkRenderingAttachmentInfo> colour, const VkRenderingAttachmentInfo* depth) {
  begin_rendering(cmd, VkRect2D{{0, 0}, {width, height}}, colour, depth);
}

void begin_rendering(VkCommandBuffer cmd, const VkRect2D& area, std::span<const VkRenderingAttachmentInfo> colour,
                     const VkRenderingAttachmentInfo* depth) {
  VkRenderingInfo rendering{};
  rendering.sType = VK_STRUCTURE_TYPE_RENDERING_INFO;
  rendering.renderArea = area;
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = static_cast<uint32_t>(colour.size());
  rendering.pColorAttachments = colour.data();
  rendering.pDepthAttachment = depth;
  vkCmdBeginRendering(cmd, &rendering);
}

void require_subgroup_arithmetic(const vk::Context& context, const char* pass) {
  VkPhysicalDeviceSubgroupProperties subgroup{};
  subgroup.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
  VkPhysicalDeviceProperties2 properties{};
  properties.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  properties.pNext = &subgroup;
  vkGetPhysicalDeviceProperties2(context.physical_device(), &properties);
  constexpr VkSubgroupFeatureFlags kNeeded = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
  if ((subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) == 0 ||
      (subgroup.supportedOperations & kNeeded) != kNeeded || subgroup.subgroupSize > 128) {
    throw std::runtime_error(std::string(pass) + ": the Vulkan device '" + context.info().name +
                             "' lacks subgroup arithmetic in compute shaders");
  }
}

vk::Sampler create_nearest_sampler(VkDevice device) {
  VkSamplerCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO;
  info.magFilter = VK_FILTER_NEAREST;
  info.minFilter = VK_FILTER_NEAREST;
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  info.addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  info.addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  VkSampler sampler = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkCreateSampler(device, &info, nullptr, &sampler));
  return vk::Sampler(device, sampler);
}

ComputePassCore ComputePassCore::create(VkDevice device, std::span<const ComputeBinding> bindings,
                                        uint32_t push_size, const char* shader, uint32_t slots) {
  constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;
  ComputePassCore core;
  core.sampler = create_nearest_sampler(device);
  std::vector<VkDescriptorSetLayoutBinding> layout_bindings;
  std::map<VkDescriptorType, uint32_t> per_type;  // descriptors of each type in one set
  for (const ComputeBinding& b : bindings) {
    layout_bindings.push_back({b.binding, b.type, 1, kCompute, nullptr});
    ++per_type[b.type];
  }
  core.set_layout = vk::create_descriptor_set_layout(device, layout_bindings);
  const VkPushConstantRange push{kCompute, 0, push_size};
  const VkDescriptorSetLayout set_layout = core.set_layout.get();
  core.layout = vk::create_pipeline_layout(device, std::span(&set_layout, 1), std::span(&push, 1));
  core.pipeline = vk::create_compute_pipeline(device, core.layout.get(),
                                              vk::find_spirv(dhr_shaders_client_modules(), shader));
  std::vector<VkDescriptorPoolSize> sizes;
  for (const auto& [type, count] : per_type) sizes.push_back({type, count * slots});
  core.pool = vk::create_descriptor_pool(device, slots, sizes);
  return core;
}

VkDescriptorSet ComputePassCore::allocate_set(VkDevice device) const {
  return vk::allocate_descriptor_set(device, pool.get(), set_layout.get());
}

void ComputePassCore::dispatch(VkCommandBuffer cmd, VkDescriptorSet set, const void* push, uint32_t push_size,
                               uint32_t width, uint32_t height, uint32_t group_size) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.get());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.get(), 0, 1, &set, 0, nullptr);
  vkCmdPushConstants(cmd, layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size, push);
  vkCmdDispatch(cmd, (width + group_size - 1) / group_size, (height + group_size - 1) / group_size, 1);
}

}  // namespace dhr::render
