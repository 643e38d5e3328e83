// Drawing a ClientScene for one camera, shared by the raster passes that shade its materials (G-buffer,
// forward): the per-material descriptor sets (set 0: the base colour texture, kClientGBufferBindingBaseColor)
// and the draw loop (bounding-sphere frustum culling, the back-face-culling pipeline for single-sided materials
// and the no-culling one for double-sided ones, ClientGBufferPush with camera-relative mesh offsets; moving meshes
// with their motion at the frame's scene time, mesh_push.hpp, culled with their moved bounding spheres).
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <vector>

#include "math/projection.hpp"
#include "vk/handle.hpp"

namespace dhr::render {

class ClientScene;
struct MovedScene;

struct GBufferDrawStats {
  uint32_t meshes_drawn = 0;
  uint32_t meshes_culled = 0;  // bounding sphere outside the view frustum
  uint64_t triangles_drawn = 0;
};

// Push-constant stages of ClientGBufferPush in every pass that draws materials.
inline constexpr VkShaderStageFlags kMaterialPushStages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

class MaterialSets {
 public:
  MaterialSets() = default;
  // One set per material of `scene` (at least one set is allocated for an empty scene).
  MaterialSets(VkDevice device, const ClientScene& scene);
  VkDescriptorSetLayout layout() const { return layout_.get(); }
  VkDescriptorSet set(uint32_t material) const { return sets_[material]; }

 private:
  vk::DescriptorSetLayout layout_;
  vk::DescriptorPool pool_;
  std::vector<VkDescriptorSet> sets_;
};

struct SceneDrawPipelines {
  VkPipelineLayout layout = VK_NULL_HANDLE;  // set 0: MaterialSets::layout(); push: ClientGBufferPush
  VkPipeline cull_back = VK_NULL_HANDLE;
  VkPipeline cull_none = VK_NULL_HANDLE;
};

// Records the draws (inside a rendering scope the caller began, viewport and scissor included). `moved`: the
// scene at the frame's scene time (null or unsampled: at rest).
GBufferDrawStats record_scene_draws(VkCommandBuffer cmd, const ClientScene& scene, const MaterialSets& materials,
                                    const SceneDrawPipelines& pipelines, const Camera& camera, double near_plane,
                                    const MovedScene* moved = nullptr);

// The motion of mesh `index` in `moved` (null: static, or no sample).
const glm::dmat4* moved_motion(const ClientScene& scene, const MovedScene* moved, uint32_t index);

}  // namespace dhr::render
