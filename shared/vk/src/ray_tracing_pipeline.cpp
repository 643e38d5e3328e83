#include "vk/ray_tracing_pipeline.hpp"

#include <cstring>
#include <stdexcept>
#include <string>

#include "vk/check.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace dhr::vk {
namespace {

VkDeviceSize align_up(VkDeviceSize value, VkDeviceSize alignment) {
  return alignment <= 1 ? value : (value + alignment - 1) / alignment * alignment;
}

}  // namespace

RayTracingPipeline::RayTracingPipeline(const Context& context, const RayTracingPipelineDesc& desc)
    : layout_(desc.layout), trace_fn_(context.rt().cmd_trace_rays) {
  const RayTracingSupport& support = context.info().ray_tracing;
  if (!support.enabled()) {
    throw std::logic_error("ray-tracing pipelines need a Context with ray tracing enabled "
                           "(ContextOptions::want_ray_tracing on a device that supports it)");
  }
  if (desc.raygen == nullptr) throw std::invalid_argument("ray-tracing pipeline: no raygen shader");
  if (desc.layout == VK_NULL_HANDLE) throw std::invalid_argument("ray-tracing pipeline: no pipeline layout");
  if (desc.max_recursion_depth > support.max_ray_recursion_depth) {
    throw std::invalid_argument("ray-tracing pipeline: recursion depth " + std::to_string(desc.max_recursion_depth) +
                                " exceeds the device's maximum " + std::to_string(support.max_ray_recursion_depth));
  }
  const VkDevice device = context.device();

  // One stage per use; groups in SBT order: raygen, miss..., hit groups...
  std::vector<ShaderModule> modules;
  std::vector<VkPipelineShaderStageCreateInfo> stages;
  auto add_stage = [&](const SpirvModule* module, VkShaderStageFlagBits stage) -> uint32_t {
    if (module == nullptr) return VK_SHADER_UNUSED_KHR;
    modules.push_back(create_shader_module(device, *module));
    VkPipelineShaderStageCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    info.stage = stage;
    info.module = modules.back().get();
    info.pName = "main";
    stages.push_back(info);
    return static_cast<uint32_t>(stages.size() - 1);
  };
  std::vector<VkRayTracingShaderGroupCreateInfoKHR> groups;
  auto add_group = [&](VkRayTracingShaderGroupTypeKHR type, uint32_t general, uint32_t closest, uint32_t any) {
    VkRayTracingShaderGroupCreateInfoKHR group{};
    group.sType = VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR;
    group.type = type;
    group.generalShader = general;
    group.closestHitShader = closest;
    group.anyHitShader = any;
    group.intersectionShader = VK_SHADER_UNUSED_KHR;
    groups.push_back(group);
  };
  add_group(VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR, add_stage(desc.raygen, VK_SHADER_STAGE_RAYGEN_BIT_KHR),
            VK_SHADER_UNUSED_KHR, VK_SHADER_UNUSED_KHR);
  for (const SpirvModule* miss : desc.miss) {
    if (miss == nullptr) throw std::invalid_argument("ray-tracing pipeline: null miss shader");
    add_group(VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR, add_stage(miss, VK_SHADER_STAGE_MISS_BIT_KHR),
              VK_SHADER_UNUSED_KHR, VK_SHADER_UNUSED_KHR);
  }
  for (const RayTracingHitGroup& hit : desc.hit_groups) {
    if (hit.closest_hit == nullptr && hit.any_hit == nullptr) {
      throw std::invalid_argument("ray-tracing pipeline: hit group without shaders");
    }
    const uint32_t closest = add_stage(hit.closest_hit, VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR);
    const uint32_t any = add_stage(hit.any_hit, VK_SHADER_STAGE_ANY_HIT_BIT_KHR);
    add_group(VK_RAY_TRACING_SHADER_GROUP_TYPE_TRIANGLES_HIT_GROUP_KHR, VK_SHADER_UNUSED_KHR, closest, any);
  }

  VkRayTracingPipelineCreateInfoKHR info{};
  info.sType = VK_STRUCTURE_TYPE_RAY_TRACING_PIPELINE_CREATE_INFO_KHR;
  info.stageCount = static_cast<uint32_t>(stages.size());
  info.pStages = stages.data();
  info.groupCount = static_cast<uint32_t>(groups.size());
  info.pGroups = groups.data();
  info.maxPipelineRayRecursionDepth = desc.max_recursion_depth;
  info.layout = desc.layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  DHR_VK_CHECK(context.rt().create_ray_tracing_pipelines(device, VK_NULL_HANDLE, VK_NULL_HANDLE, 1, &info, nullptr,
                                                         &pipeline));
  pipeline_ = Pipeline(device, pipeline);

  // Shader binding table: each region starts at a base-aligned address; records are handle-aligned.
  const uint32_t handle_size = support.shader_group_handle_size;
  const VkDeviceSize record = align_up(handle_size, support.shader_group_handle_alignment);
  const VkDeviceSize base = std::max<VkDeviceSize>(1, support.shader_group_base_alignment);
  const VkDeviceSize miss_count = desc.miss.size();
  const VkDeviceSize hit_count = desc.hit_groups.size();
  const VkDeviceSize raygen_size = align_up(record, base);  // raygen: stride must equal size
  const VkDeviceSize miss_size = align_up(miss_count * record, base);
  const VkDeviceSize hit_size = align_up(hit_count * record, base);
  const VkDeviceSize total = raygen_size + miss_size + hit_size;

  std::vector<uint8_t> handles(size_t{handle_size} * groups.size());
  DHR_VK_CHECK(context.rt().get_ray_tracing_shader_group_handles(device, pipeline, 0,
                                                                 static_cast<uint32_t>(groups.size()),
                                                                 handles.size(), handles.data()));
  std::vector<uint8_t> table(total, 0);
  auto place = [&](uint32_t group, VkDeviceSize offset) {
    std::memcpy(table.data() + offset, handles.data() + size_t{handle_size} * group, handle_size);
  };
  place(0, 0);
  for (uint32_t i = 0; i < miss_count; ++i) place(1 + i, raygen_size + i * record);
  for (uint32_t i = 0; i < hit_count; ++i) {
    place(static_cast<uint32_t>(1 + miss_count + i), raygen_size + miss_size + i * record);
  }

  // Over-allocate so the table can start at a base-aligned device address.
  sbt_ = Buffer(context, total + base,
                VK_BUFFER_USAGE_SHADER_BINDING_TABLE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                    VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  const VkDeviceAddress start = align_up(sbt_.address(), base);
  upload_to_buffer(context, sbt_, table.data(), total, start - sbt_.address());
  raygen_ = {start, raygen_size, raygen_size};
  if (miss_count > 0) miss_ = {start + raygen_size, record, miss_size};
  if (hit_count > 0) hit_ = {start + raygen_size + miss_size, record, hit_size};
}

void RayTracingPipeline::bind(VkCommandBuffer cmd) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, pipeline_.get());
}

void RayTracingPipeline::trace(VkCommandBuffer cmd, uint32_t width, uint32_t height, uint32_t depth) const {
  trace_fn_(cmd, &raygen_, &miss_, &hit_, &callable_, width, height, depth);
}

}  // namespace dhr::vk
