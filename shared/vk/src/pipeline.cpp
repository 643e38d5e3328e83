#include "vk/pipeline.hpp"

#include <stdexcept>
#include <string>

#include "vk/check.hpp"

namespace dhr::vk {

ShaderModule create_shader_module(VkDevice device, const SpirvModule& module) {
  constexpr uint32_t kSpirvMagic = 0x07230203;
  const std::string name = module.name != nullptr ? module.name : "(unnamed)";
  if (module.words == nullptr || module.word_count < 5 || module.words[0] != kSpirvMagic) {
    throw std::invalid_argument("shader module '" + name + "' is not valid SPIR-V (empty or bad magic number)");
  }
  VkShaderModuleCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  info.codeSize = module.word_count * sizeof(uint32_t);
  info.pCode = module.words;
  VkShaderModule handle = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkCreateShaderModule(device, &info, nullptr, &handle));
  return ShaderModule(device, handle);
}

DescriptorSetLayout create_descriptor_set_layout(VkDevice device,
                                                 std::span<const VkDescriptorSetLayoutBinding> bindings,
                                                 VkDescriptorSetLayoutCreateFlags flags) {
  VkDescriptorSetLayoutCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  info.flags = flags;
  info.bindingCount = static_cast<uint32_t>(bindings.size());
  info.pBindings = bindings.data();
  VkDescriptorSetLayout handle = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkCreateDescriptorSetLayout(device, &info, nullptr, &handle));
  return DescriptorSetLayout(device, handle);
}

PipelineLayout create_pipeline_layout(VkDevice device, std::span<const VkDescriptorSetLayout> set_layouts,
                                      std::span<const VkPushConstantRange> push_constants) {
  VkPipelineLayoutCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  info.setLayoutCount = static_cast<uint32_t>(set_layouts.size());
  info.pSetLayouts = set_layouts.data();
  info.pushConstantRangeCount = static_cast<uint32_t>(push_constants.size());
  info.pPushConstantRanges = push_constants.data();
  VkPipelineLayout handle = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkCreatePipelineLayout(device, &info, nullptr, &handle));
  return PipelineLayout(device, handle);
}

DescriptorPool create_descriptor_pool(VkDevice device, uint32_t max_sets, std::span<const VkDescriptorPoolSize> sizes,
                                      VkDescriptorPoolCreateFlags flags) {
  VkDescriptorPoolCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  info.flags = flags;
  info.maxSets = max_sets;
  info.poolSizeCount = static_cast<uint32_t>(sizes.size());
  info.pPoolSizes = sizes.data();
  VkDescriptorPool handle = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkCreateDescriptorPool(device, &info, nullptr, &handle));
  return DescriptorPool(device, handle);
}

VkDescriptorSet allocate_descriptor_set(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout) {
  VkDescriptorSetAllocateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  info.descriptorPool = pool;
  info.descriptorSetCount = 1;
  info.pSetLayouts = &layout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkAllocateDescriptorSets(device, &info, &set));
  return set;
}

Pipeline create_compute_pipeline(VkDevice device, VkPipelineLayout layout, const SpirvModule& module,
                                 const char* entry_point) {
  const ShaderModule shader = create_shader_module(device, module);
  VkComputePipelineCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
  info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = shader.get();
  info.stage.pName = entry_point;
  info.layout = layout;
  VkPipeline handle = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &handle));
  return Pipeline(device, handle);
}

void write_buffer_descriptor(VkDevice device, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                             VkBuffer buffer, VkDeviceSize offset, VkDeviceSize range) {
  const VkDescriptorBufferInfo info{buffer, offset, range};
  VkWriteDescriptorSet write{};
  write.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
  write.dstSet = set;
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = type;
  write.pBufferInfo = &info;
  vkUpdateDescriptorSets(device, 1, &write, 0, nullptr);
}

void write_image_descriptor(VkDevice device, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                            VkImageView view, VkImageLayout layout, VkSampler sampler) {
  const VkDescriptorImageInfo info{sampler, view, layout};
  VkWriteDescriptorSet write{};
  write.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
  write.dstSet = set;
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = type;
  write.pImageInfo = &info;
  vkUpdateDescriptorSets(device, 1, &write, 0, nullptr);
}

void write_acceleration_structure_descriptor(VkDevice device, VkDescriptorSet set, uint32_t binding,
                                             VkAccelerationStructureKHR structure) {
  VkWriteDescriptorSetAccelerationStructureKHR as_info{};
  as_info.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR;
  as_info.accelerationStructureCount = 1;
  as_info.pAccelerationStructures = &structure;
  VkWriteDescriptorSet write{};
  write.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
  write.pNext = &as_info;
  write.dstSet = set;
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
  vkUpdateDescriptorSets(device, 1, &write, 0, nullptr);
}

}  // namespace dhr::vk
