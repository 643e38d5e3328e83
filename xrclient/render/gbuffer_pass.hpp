// G-buffer pass: rasterizes a ClientScene for one eye with dynamic rendering into
//   depth  D32_SFLOAT           reversed-Z (clear 0 = background, compare GREATER), depth = near / distance
//   normal R16G16B16A16_SFLOAT  world-space unit normal (xyz), w = 1 on surfaces, 0 on background
//   albedo R8G8B8A8_UNORM       linear albedo = base colour factor x texture, a = 1 on surfaces
// Single-sided materials cull back faces (glTF: counter-clockwise front faces); double-sided ones draw
// both sides with the normal flipped on back faces. World positions come back from depth
// (render_camera.hpp: world_point_from_depth).
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "math/projection.hpp"
#include "render/scene_draw.hpp"
#include "vk/handle.hpp"
#include "vk/image.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

class ClientScene;

inline constexpr VkFormat kGBufferDepthFormat = VK_FORMAT_D32_SFLOAT;
inline constexpr VkFormat kGBufferNormalFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
inline constexpr VkFormat kGBufferAlbedoFormat = VK_FORMAT_R8G8B8A8_UNORM;

struct GBuffer {
  vk::Image depth;   // usage: depth attachment, sampled, transfer src/dst
  vk::Image normal;  // usage: colour attachment, sampled, transfer src
  vk::Image albedo;  // usage: colour attachment, sampled, transfer src

  static GBuffer create(const vk::Context& context, Extent extent);
  Extent extent() const { return Extent{depth.width(), depth.height()}; }
};

class GBufferPass {
 public:
  // Keeps a reference to the scene: it must outlive the pass.
  GBufferPass(const vk::Context& context, const ClientScene& scene);

  // Records the pass for `camera` (the display camera; its extent must equal the targets', else
  // std::invalid_argument). Leaves the three images in SHADER_READ_ONLY_OPTIMAL, their writes visible to
  // later shader reads.
  // `moved`: the scene at the frame's scene time (null: at rest).
  GBufferDrawStats record(VkCommandBuffer cmd, GBuffer& targets, const Camera& camera, double near_plane,
                          const MovedScene* moved = nullptr) const;

 private:
  const ClientScene* scene_;
  MaterialSets materials_;
  vk::PipelineLayout layout_;
  vk::Pipeline cull_back_;
  vk::Pipeline cull_none_;
};

}  // namespace dhr::render
