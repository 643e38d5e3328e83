#include "render/gbuffer_pass.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include "dhr_shaders_client.hpp"
#include "render/client_scene.hpp"
#include "render/pass_util.hpp"
#include "render/render_camera.hpp"
#include "shaders/shader_interface.h"
#include "vk/context.hpp"
#include "vk/graphics_pipeline.hpp"
#include "vk/pipeline.hpp"

namespace dhr::render {
namespace {

using namespace dhr::shader;  // binding numbers and flags shared with the GLSL

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
  materials_ = MaterialSets(device, scene);
  const VkPushConstantRange push{kMaterialPushStages, 0, sizeof(shader::ClientGBufferPush)};
  const VkDescriptorSetLayout set_layout = materials_.layout();
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
}

GBufferDrawStats GBufferPass::record(VkCommandBuffer cmd, GBuffer& targets, const Camera& camera,
                                     double near_plane, const MovedScene* moved) const {
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
      cleared_attachment(targets.normal.view(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, zero),
      cleared_attachment(targets.albedo.view(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, zero)};
  VkClearValue depth_clear{};
  depth_clear.depthStencil = {0.0f, 0};  // reversed-Z: 0 is infinitely far
  const VkRenderingAttachmentInfo depth =
      cleared_attachment(targets.depth.view(), VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, depth_clear);
  begin_rendering(cmd, extent.width, extent.height, colour, &depth);

  vk::set_viewport_and_scissor(cmd, {extent.width, extent.height});
  const GBufferDrawStats stats =
      record_scene_draws(cmd, *scene_, materials_, {layout_.get(), cull_back_.get(), cull_none_.get()}, camera, near_plane, moved);
  vkCmdEndRendering(cmd);

  targets.depth.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  targets.normal.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  targets.albedo.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  return stats;
}

}  // namespace dhr::render
