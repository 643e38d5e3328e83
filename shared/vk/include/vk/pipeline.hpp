// Shader modules, layouts, descriptor pools/sets and compute pipelines as RAII owners
// (see handle.hpp for the owner types). Ray-tracing pipelines: ray_tracing_pipeline.hpp.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>

#include "vk/handle.hpp"
#include "vk/spirv.hpp"

namespace dhr::vk {

// Throws std::invalid_argument when `module` is empty or not SPIR-V.
ShaderModule create_shader_module(VkDevice device, const SpirvModule& module);

DescriptorSetLayout create_descriptor_set_layout(VkDevice device,
                                                 std::span<const VkDescriptorSetLayoutBinding> bindings,
                                                 VkDescriptorSetLayoutCreateFlags flags = 0);

PipelineLayout create_pipeline_layout(VkDevice device, std::span<const VkDescriptorSetLayout> set_layouts,
                                      std::span<const VkPushConstantRange> push_constants = {});

DescriptorPool create_descriptor_pool(VkDevice device, uint32_t max_sets, std::span<const VkDescriptorPoolSize> sizes,
                                      VkDescriptorPoolCreateFlags flags = 0);

// The set lives as long as the pool (freed with it).
VkDescriptorSet allocate_descriptor_set(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout);

Pipeline create_compute_pipeline(VkDevice device, VkPipelineLayout layout, const SpirvModule& module,
                                 const char* entry_point = "main");

// Single-descriptor writes (array element 0).
void write_buffer_descriptor(VkDevice device, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                             VkBuffer buffer, VkDeviceSize offset = 0, VkDeviceSize range = VK_WHOLE_SIZE);
void write_image_descriptor(VkDevice device, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                            VkImageView view, VkImageLayout layout, VkSampler sampler = VK_NULL_HANDLE);
void write_acceleration_structure_descriptor(VkDevice device, VkDescriptorSet set, uint32_t binding,
                                             VkAccelerationStructureKHR structure);

}  // namespace dhr::vk
