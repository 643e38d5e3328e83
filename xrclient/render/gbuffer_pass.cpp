#include "render/gbuffer_pass.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include "dhr_shaders_client.hpp"
#include "render/client_scene.hpp"
#include "render/pass_util.hpp"
#include "render/render_camera.hpp"
#include "shader_interface.h"
#include "vk/context.hpp"
#include "vk/graphics_pipeline.hpp"
#include "vk/pipeline.hpp"

namespace dhr::render {
namespace {

using namespace dhr::shader;  // binding numbers and flags shared with the GLSL

constexpr VkShaderStageFlags kPushStages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

VkRenderingAttachmentInfo clear_attachment(VkImageView view, VkImageLayout layout, VkClearValue clear) {
  VkRenderingAttachmentInfo a{};
  a.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
  a.imageView = view;
  a.imageLayout = layout;
  a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  a.clearValue = clear;
  return a;
}

}  // namespace

GBuffer GBuffer::create(const vk::Context& context, Extent extent) {
  constexpr VkImageUsageFlags kColour =
      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  GBuffer g;
  g.depth = vk::Image(context, extent.width, extent.height, kGBufferDepthFormat,
                      VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                          VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
  g.normal = vk::Image(context, extent.width, extent.height, kGBufferNormalFormat, kColour);
  g.albedo = vk::Image(context, extent.width, extent.height, kGBufferAlbedoFormat, kColour);
  return g;
}

GBufferPass::GBufferPass(const vk::Context& context, const ClientScene& scene) : scene_(&scene) {
  const VkDevice device = context.device();
  const VkDescriptorSetLayoutBinding binding{kClientGBufferBindingBaseColor, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                             1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
  set_layout_ = vk::create_descriptor_set_layout(device, std::span(&binding, 1));
  const VkPushConstantRange push{kPushStages, 0, sizeof(shader::ClientGBufferPush)};
  const VkDescriptorSetLayout set_layout = set_layout_.get();
  layout_ = vk::create_pipeline_layout(device, std::span(&set_layout, 1), std::span(&push, 1));

  const auto modules = dhr_shaders_client_modules();
  const std::array<VkFormat, 2> colour_formats = {kGBufferNormalFormat, kGBufferAlbedoFormat};
  vk::GraphicsPipelineDesc desc;
  desc.vertex = &vk::find_spirv(modules, "gbuffer.vert");
  desc.fragment = &vk::find_spirv(modules, "gbuffer.frag");
  desc.vertex_bindings = ClientScene::vertex_bindings();
  desc.vertex_attributes = ClientScene::vertex_attributes();
  desc.color_formats = colour_formats;
  desc.depth_format = kGBufferDepthFormat;
  desc.depth_compare = VK_COMPARE_OP_GREATER;
  // The projection flips y (Vulkan clip space is y-down), so the image is upright and a triangle that is
  // counter-clockwise as seen by the eye stays counter-clockwise in framebuffer terms.
  desc.front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  desc.cull_mode = VK_CULL_MODE_BACK_BIT;
  cull_back_ = vk::create_graphics_pipeline(device, layout_.get(), desc);
  desc.cull_mode = VK_CULL_MODE_NONE;
  cull_none_ = vk::create_graphics_pipeline(device, layout_.get(), desc);

  // One descriptor set per material: its texture and sampler never change.
  const uint32_t set_count = std::max<uint32_t>(1, static_cast<uint32_t>(scene.materials().size()));
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, set_count};
  pool_ = vk::create_descriptor_pool(device, set_count, std::span(&size, 1));
  for (const ClientMaterial& m : scene.materials()) {
    const VkDescriptorSet set = vk::allocate_descriptor_set(device, pool_.get(), set_layout_.get());
    vk::write_image_descriptor(device, set, kClientGBufferBindingBaseColor, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                               scene.textures()[m.texture].view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                               scene.samplers()[m.sampler].get());
    material_sets_.push_back(set);
  }
}

GBufferDrawStats GBufferPass::record(VkCommandBuffer cmd, GBuffer& targets, const Camera& camera,
                                     double near_plane) const {
  const Extent extent = targets.extent();
  if (!(camera.extent == extent)) {
    throw std::invalid_argument("G-buffer pass: camera is " + std::to_string(camera.extent.width) + "x" +
                                std::to_string(camera.extent.height) + ", targets are " +
                                std::to_string(extent.width) + "x" + std::to_string(extent.height));
  }
  discard_to_layout(cmd, targets.depth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  for (vk::Image* image : {&targets.normal, &targets.albedo}) {
    discard_to_layout(cmd, *image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  }

  VkClearValue zero{};
  const std::array<VkRenderingAttachmentInfo, 2> colour = {
      clear_attachment(targets.normal.view(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, zero),
      clear_attachment(targets.albedo.view(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, zero)};
  VkClearValue depth_clear{};
  depth_clear.depthStencil = {0.0f, 0};  // reversed-Z: 0 is infinitely far
  const VkRenderingAttachmentInfo depth =
      clear_attachment(targets.depth.view(), VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, depth_clear);
  VkRenderingInfo rendering{};
  rendering.sType = VK_STRUCTURE_TYPE_RENDERING_INFO;
  rendering.renderArea = {{0, 0}, {extent.width, extent.height}};
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = static_cast<uint32_t>(colour.size());
  rendering.pColorAttachments = colour.data();
  rendering.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &rendering);

  GBufferDrawStats stats;
  const ClientScene& scene = *scene_;
  if (scene.indices()) {
    vk::set_viewport_and_scissor(cmd, {extent.width, extent.height});
    scene.bind_geometry(cmd);

    shader::ClientGBufferPush push{};
    const std::array<float, 16> vp = matrix_floats(camera_relative_view_projection(camera, near_plane));
    std::copy(vp.begin(), vp.end(), push.view_proj);
    VkPipeline bound = VK_NULL_HANDLE;
    for (const ClientMesh& mesh : scene.meshes()) {
      if (!sphere_may_be_visible(camera, mesh.origin, mesh.radius)) {
        ++stats.meshes_culled;
        continue;
      }
      const ClientMaterial& material = scene.materials()[mesh.material];
      const VkPipeline pipeline = material.double_sided ? cull_none_.get() : cull_back_.get();
      if (pipeline != bound) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
        bound = pipeline;
      }
      const VkDescriptorSet set = material_sets_[mesh.material];
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set, 0, nullptr);
      const glm::vec3 t = camera_relative_offset(mesh.origin, camera);
      push.translation_x = t.x;
      push.translation_y = t.y;
      push.translation_z = t.z;
      push.flags = (material.double_sided ? kClientMaterialDoubleSided : 0u) |
                   (material.alpha_mask ? kClientMaterialAlphaMask : 0u);
      push.base_color_r = material.base_color_factor.r;
      push.base_color_g = material.base_color_factor.g;
      push.base_color_b = material.base_color_factor.b;
      push.base_color_a = material.base_color_factor.a;
      push.alpha_cutoff = material.alpha_cutoff;
      vkCmdPushConstants(cmd, layout_.get(), kPushStages, 0, sizeof(push), &push);
      vkCmdDrawIndexed(cmd, mesh.index_count, 1, mesh.first_index, mesh.vertex_offset, 0);
      ++stats.meshes_drawn;
      stats.triangles_drawn += mesh.index_count / 3;
    }
  }
  vkCmdEndRendering(cmd);

  targets.depth.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  targets.normal.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  targets.albedo.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  return stats;
}

}  // namespace dhr::render
