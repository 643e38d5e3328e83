#include "render/scene_draw.hpp"

#include <algorithm>
#include <array>
#include <span>

#include "render/client_scene.hpp"
#include "render/mesh_push.hpp"
#include "render/client_motion.hpp"
#include "render/render_camera.hpp"
#include "shaders/shader_interface.h"
#include "vk/pipeline.hpp"

namespace dhr::render {

using namespace dhr::shader;

MaterialSets::MaterialSets(VkDevice device, const ClientScene& scene) {
  const VkDescriptorSetLayoutBinding binding{kClientGBufferBindingBaseColor, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                             1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
  layout_ = vk::create_descriptor_set_layout(device, std::span(&binding, 1));
  // One descriptor set per material: its texture and sampler never change.
  const uint32_t set_count = std::max<uint32_t>(1, static_cast<uint32_t>(scene.materials().size()));
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, set_count};
  pool_ = vk::create_descriptor_pool(device, set_count, std::span(&size, 1));
  for (const ClientMaterial& m : scene.materials()) {
    const VkDescriptorSet set = vk::allocate_descriptor_set(device, pool_.get(), layout_.get());
    vk::write_image_descriptor(device, set, kClientGBufferBindingBaseColor, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                               scene.textures()[m.texture].view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                               scene.samplers()[m.sampler].get());
    sets_.push_back(set);
  }
}

const glm::dmat4* moved_motion(const ClientScene& scene, const MovedScene* moved, uint32_t index) {
  if (moved == nullptr || !moved->sampled || !scene.motion().mesh_moves(index)) return nullptr;
  return &moved->motion[index];
}

GBufferDrawStats record_scene_draws(VkCommandBuffer cmd, const ClientScene& scene, const MaterialSets& materials,
                                    const SceneDrawPipelines& pipelines, const Camera& camera, double near_plane,
                                    const MovedScene* moved) {
  GBufferDrawStats stats;
  if (!scene.indices()) return stats;
  scene.bind_geometry(cmd);
  ClientGBufferPush push{};
  const MeshPush transform(camera_relative_view_projection(camera, near_plane), camera.T_world_eye.position);
  VkPipeline bound = VK_NULL_HANDLE;
  for (uint32_t i = 0; i < scene.meshes().size(); ++i) {
    const ClientMesh& mesh = scene.meshes()[i];
    const glm::dmat4* motion = moved_motion(scene, moved, i);
    const glm::dvec3 centre = motion ? moved->centre[i] : mesh.origin;
    const double radius = motion ? moved->radius[i] : mesh.radius;
    if (!sphere_may_be_visible(camera, centre, radius)) {
      ++stats.meshes_culled;
      continue;
    }
    const ClientMaterial& material = scene.materials()[mesh.material];
    const VkPipeline pipeline = material.double_sided ? pipelines.cull_none : pipelines.cull_back;
    if (pipeline != bound) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
      bound = pipeline;
    }
    const VkDescriptorSet set = materials.set(mesh.material);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines.layout, 0, 1, &set, 0, nullptr);
    push.flags = (material.double_sided ? kClientMaterialDoubleSided : 0u) |
                 (material.alpha_mask ? kClientMaterialAlphaMask : 0u);
    transform.set(push, mesh, motion);
    push.base_color_r = material.base_color_factor.r;
    push.base_color_g = material.base_color_factor.g;
    push.base_color_b = material.base_color_factor.b;
    push.base_color_a = material.base_color_factor.a;
    push.alpha_cutoff = material.alpha_cutoff;
    vkCmdPushConstants(cmd, pipelines.layout, kMaterialPushStages, 0, sizeof(push), &push);
    vkCmdDrawIndexed(cmd, mesh.index_count, 1, mesh.first_index, mesh.vertex_offset, 0);
    ++stats.meshes_drawn;
    stats.triangles_drawn += mesh.index_count / 3;
  }
  return stats;
}

}  // namespace dhr::render
