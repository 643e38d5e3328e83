// The visibility ray-tracing pipeline: descriptor layout, SBT (raygen; primary and shadow miss; one hit
// group), and the descriptor writes.
#include "trace/vulkan/vulkan_tracer_internal.hpp"

#include "dhr_shaders_server.hpp"
#include "vk/pipeline.hpp"
#include "vk/spirv.hpp"

#include <array>

namespace dhr::server::detail {

TracerPipeline create_tracer_pipeline(const vk::Context& context) {
  const VkDevice device = context.device();
  TracerPipeline out;
  constexpr VkShaderStageFlags kStage = VK_SHADER_STAGE_RAYGEN_BIT_KHR;
  std::array<VkDescriptorSetLayoutBinding, 11> bindings{};
  const uint32_t binding_ids[11] = {shader::kVisBindingTlas,        shader::kVisBindingLights,
                                    shader::kVisBindingMeshes,      shader::kVisBindingPositions,
                                    shader::kVisBindingNormals,     shader::kVisBindingIndices,
                                    shader::kVisBindingPermutation, shader::kVisBindingMasks,
                                    shader::kVisBindingCounters,    shader::kVisBindingSoftLights,
                                    shader::kVisBindingLightSlots};
  for (size_t i = 0; i < bindings.size(); ++i) {
    bindings[i].binding = binding_ids[i];
    const bool tlas = binding_ids[i] == shader::kVisBindingTlas;
    bindings[i].descriptorType = tlas ? VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[i].descriptorCount = 1;
    bindings[i].stageFlags = kStage;
  }
  out.set_layout = vk::create_descriptor_set_layout(device, bindings);
  const VkDescriptorSetLayout set_layout = out.set_layout.get();
  const VkPushConstantRange push{kStage, 0, sizeof(shader::VisPushConstants)};
  out.layout = vk::create_pipeline_layout(device, std::span<const VkDescriptorSetLayout>(&set_layout, 1),
                                          std::span<const VkPushConstantRange>(&push, 1));
  const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, 1},
                                        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 10}};
  out.pool = vk::create_descriptor_pool(device, 1, sizes);
  out.set = vk::allocate_descriptor_set(device, out.pool.get(), set_layout);

  const auto modules = dhr_shaders_server_modules();
  vk::RayTracingPipelineDesc desc;
  desc.raygen = &vk::find_spirv(modules, "visibility.rgen");
  desc.miss = {&vk::find_spirv(modules, "visibility.rmiss"), &vk::find_spirv(modules, "shadow.rmiss")};
  desc.hit_groups = {vk::RayTracingHitGroup{&vk::find_spirv(modules, "visibility.rchit"), nullptr}};
  desc.layout = out.layout.get();
  desc.max_recursion_depth = 1;  // shadow rays are traced from the raygen shader, not from hit shaders
  out.pipeline = vk::RayTracingPipeline(context, desc);
  return out;
}

void write_scene_descriptors(const vk::Context& context, const TracerPipeline& pipeline, const GpuScene& scene) {
  const VkDevice device = context.device();
  vk::write_acceleration_structure_descriptor(device, pipeline.set, shader::kVisBindingTlas, scene.tlas.handle());
  const std::pair<uint32_t, const vk::Buffer*> buffers[] = {
      {shader::kVisBindingLights, &scene.lights},       {shader::kVisBindingMeshes, &scene.meshes},
      {shader::kVisBindingPositions, &scene.positions}, {shader::kVisBindingNormals, &scene.normals},
      {shader::kVisBindingIndices, &scene.indices},     {shader::kVisBindingPermutation, &scene.permutation},
      {shader::kVisBindingSoftLights, &scene.soft_lights}, {shader::kVisBindingLightSlots, &scene.light_slots}};
  for (const auto& [binding, buffer] : buffers)
    vk::write_buffer_descriptor(device, pipeline.set, binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffer->handle());
}

void write_frame_descriptors(const vk::Context& context, const TracerPipeline& pipeline, const vk::Buffer& masks,
                             const vk::Buffer& counters) {
  const VkDevice device = context.device();
  vk::write_buffer_descriptor(device, pipeline.set, shader::kVisBindingMasks, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                              masks.handle());
  vk::write_buffer_descriptor(device, pipeline.set, shader::kVisBindingCounters, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                              counters.handle());
}

}  // namespace dhr::server::detail
