#include "render/traced_depth_splat.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "render/render_camera.hpp"
#include "shaders/shader_interface.h"
#include "vk/barriers.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace dhr::render {

namespace {

struct SplatPush {
  std::array<float, 4> rot_x, rot_y, rot_z, trans, source_tan, target_tan;
  std::array<uint32_t, 4> size;
  float near_plane;
};
static_assert(sizeof(SplatPush) == 116);

// The source eye's points in the target eye: q = rotation * p + translation.
struct EyeToEye {
  glm::dmat3 rotation;
  glm::dvec3 translation;
};
EyeToEye eye_to_eye(const Camera& source, const Camera& target) {
  const glm::dmat3 target_from_world = glm::transpose(eye_to_world_rotation(target));
  return {target_from_world * eye_to_world_rotation(source),
          target_from_world * (source.T_world_eye.position - target.T_world_eye.position)};
}

std::array<float, 4> tangents_per_pixel(const Camera& c) {
  return {static_cast<float>(c.tangents.left), static_cast<float>(c.tangents.up),
          static_cast<float>(c.tangents.width() / c.extent.width),
          static_cast<float>(c.tangents.height() / c.extent.height)};
}

}  // namespace

TracedDepthSplat::TracedDepthSplat(const vk::Context& context, uint32_t slots, uint32_t per_slot)
    : context_(&context), per_slot_(per_slot) {
  if (slots == 0 || per_slot == 0) throw std::invalid_argument("TracedDepthSplat: zero slots");
  const std::array<ComputeBinding, 2> bindings = {
      {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}, {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}}};
  core_ = ComputePassCore::create(context.device(), bindings, sizeof(SplatPush), "traced_depth_splat.comp",
                                  slots * per_slot);
  uses_.resize(size_t{slots} * per_slot);
  for (Use& use : uses_) use.set = core_.allocate_set(context.device());
}

void TracedDepthSplat::record(VkCommandBuffer cmd, uint32_t slot, uint32_t index, const vk::Image& source_depth,
                              const Camera& source, vk::Image& target, const Camera& target_camera,
                              double near_plane) {
  const size_t at = size_t{slot} * per_slot_ + index;
  if (index >= per_slot_ || at >= uses_.size()) throw std::invalid_argument("TracedDepthSplat: slot out of range");
  if (source_depth.width() != source.extent.width || source_depth.height() != source.extent.height ||
      target.width() != target_camera.extent.width || target.height() != target_camera.extent.height) {
    throw std::invalid_argument("TracedDepthSplat: an image differs in size from its camera");
  }
  Use& use = uses_[at];
  const VkDeviceSize bytes = VkDeviceSize{target.width()} * target.height() * 4;
  if (use.texels.size() < bytes) {
    use.texels = vk::Buffer(*context_, bytes,
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                            VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  }
  const VkDevice device = context_->device();
  vk::write_image_descriptor(device, use.set, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, source_depth.view(),
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, core_.sampler.get());
  vk::write_buffer_descriptor(device, use.set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, use.texels.handle(), 0, bytes);

  // 0 = no surface; the buffer's previous copy (an earlier frame of this slot) is done by the slot's contract.
  vkCmdFillBuffer(cmd, use.texels.handle(), 0, bytes, 0);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  const EyeToEye m = eye_to_eye(source, target_camera);
  SplatPush push{};
  for (int r = 0; r < 3; ++r) {
    std::array<float, 4>& row = r == 0 ? push.rot_x : r == 1 ? push.rot_y : push.rot_z;
    row = {static_cast<float>(m.rotation[0][r]), static_cast<float>(m.rotation[1][r]),
           static_cast<float>(m.rotation[2][r]), 0.0f};
  }
  push.trans = {static_cast<float>(m.translation.x), static_cast<float>(m.translation.y),
                static_cast<float>(m.translation.z), 0.0f};
  push.source_tan = tangents_per_pixel(source);
  push.target_tan = tangents_per_pixel(target_camera);
  push.size = {source.extent.width, source.extent.height, target.width(), target.height()};
  push.near_plane = static_cast<float>(near_plane);
  core_.dispatch(cmd, use.set, &push, sizeof(push), source.extent.width, source.extent.height,
                 shader::kClientWarpGroupSize);

  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  discard_to_layout(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1};
  region.imageExtent = {target.width(), target.height(), 1};
  vkCmdCopyBufferToImage(cmd, use.texels.handle(), target.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  target.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

std::vector<float> splat_traced_depth_reference(std::span<const float> source_depth, const Camera& source,
                                                const Camera& target, double near_plane) {
  const uint32_t sw = source.extent.width, sh = source.extent.height;
  const uint32_t tw = target.extent.width, th = target.extent.height;
  if (source_depth.size() != size_t{sw} * sh) {
    throw std::invalid_argument("splat_traced_depth_reference: " + std::to_string(source_depth.size()) +
                                " depth values for a " + std::to_string(sw) + "x" + std::to_string(sh) + " camera");
  }
  const EyeToEye m = eye_to_eye(source, target);
  std::vector<float> out(size_t{tw} * th, 0.0f);
  for (uint32_t y = 0; y < sh; ++y) {
    for (uint32_t x = 0; x < sw; ++x) {
      const double d = source_depth[size_t{y} * sw + x];
      if (!(d > 0.0)) continue;
      const glm::dvec3 q = m.rotation * eye_point_from_depth(source, near_plane, x + 0.5, y + 0.5, d) + m.translation;
      const double zt = -q.z;
      if (!(zt > near_plane)) continue;
      const glm::dvec2 pixel = target.tangent_to_pixel(q.x / zt, q.y / zt);
      if (!(pixel.x >= 0.0 && pixel.y >= 0.0 && pixel.x < tw && pixel.y < th)) continue;
      const size_t tx = std::min<size_t>(static_cast<size_t>(pixel.x), tw - 1);
      const size_t ty = std::min<size_t>(static_cast<size_t>(pixel.y), th - 1);
      float& texel = out[ty * tw + tx];
      texel = std::max(texel, static_cast<float>(near_plane / zt));
    }
  }
  return out;
}

}  // namespace dhr::render
