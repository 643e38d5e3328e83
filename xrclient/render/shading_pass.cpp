#include "render/shading_pass.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "scene/lighting.hpp"
#include "dhr_shaders_client.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/light_layout.hpp"
#include "render/pass_util.hpp"
#include "render/warp_pass.hpp"
#include "render/render_camera.hpp"
#include "shaders/shader_interface.h"
#include "vk/barriers.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace dhr::render {
namespace {

using namespace dhr::shader;  // binding numbers and flags shared with the GLSL

constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;

bool same_extent(const vk::Image& image, const Extent& extent) {
  return image.width() == extent.width && image.height() == extent.height;
}

}  // namespace

WarpOutputs warp_outputs_for(ShadingView view) {
  return WarpOutputs{view == ShadingView::kLightVisibility || view == ShadingView::kUnknown,
                           view == ShadingView::kMotion};
}

bool debug_outputs_available(ShadingView view, const WarpTargets& targets) {
  const WarpOutputs needed = warp_outputs_for(view);
  return (!needed.status || targets.has_status()) && (!needed.motion || targets.has_motion());
}

vk::Image create_shading_output(const vk::Context& context, Extent extent) {
  return vk::Image(context, extent.width, extent.height, kShadingOutputFormat,
                   VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
}

ShadingPass::ShadingPass(const vk::Context& context, uint32_t slots, const LightSlots* light_slots)
    : context_(&context) {
  if (slots == 0) throw std::invalid_argument("ShadingPass needs at least one slot");
  if (light_slots && !light_slots->is_identity()) light_slots_ = *light_slots;
  const VkDevice device = context.device();
  const std::array<ComputeBinding, 10> bindings = {{
      {kClientShadingBindingDepth, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
      {kClientShadingBindingNormal, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
      {kClientShadingBindingAlbedo, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
      {kClientShadingBindingMask, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {kClientShadingBindingStatus, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {kClientShadingBindingMotion, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {kClientShadingBindingLights, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {kClientShadingBindingOutput, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {kClientShadingBindingLightSlots, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {kClientShadingBindingSoft, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
  }};
  core_ = ComputePassCore::create(device, bindings, sizeof(ClientShadingPush), "shading.comp", slots);
  slots_.resize(slots);
  // The grid's origin words are not read: the push constants give it relative to each frame's eye.
  const std::vector<uint32_t> table =
      light_slots_ ? light_slots_->gpu_words(glm::dvec3(0.0)) : LightSlots::identity(0).gpu_words(glm::dvec3(0.0));
  light_slot_table = vk::create_buffer_with_data(context, std::span<const uint32_t>(table),
                                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  const size_t max_lights = light_slots_ ? light_slots_->light_count() : kMaxLights;
  for (Slot& s : slots_) {
    s.lights = vk::Buffer(context, std::max<size_t>(max_lights, 1) * sizeof(PackedLight),
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
    s.set = core_.allocate_set(device);
  }
}

void ShadingPass::record(VkCommandBuffer cmd, uint32_t slot_index, GBuffer& gbuffer, WarpTargets& warp,
                         const Camera& display, double near_plane, std::span<const SceneLight> lights,
                         const ShadingSettings& settings, vk::Image& output) {
  if (slot_index >= slots_.size()) throw std::invalid_argument("shading pass: slot out of range");
  const size_t max_lights = light_slots_ ? light_slots_->light_count() : kMaxLights;
  if (lights.size() > max_lights)
    throw std::invalid_argument("shading pass: " + std::to_string(lights.size()) + " lights, its fields hold " +
                                std::to_string(max_lights));
  const Extent extent = display.extent;
  if (!same_extent(gbuffer.depth, extent) || !same_extent(warp.mask, extent) || !same_extent(output, extent)) {
    throw std::invalid_argument("shading pass: display camera, G-buffer, warp and output differ in size");
  }
  if (!debug_outputs_available(settings.view, warp)) {
    throw std::invalid_argument("shading pass: the debug view needs warp outputs that were not allocated");
  }
  Slot& slot = slots_[slot_index];

  // Eye-relative light positions, subtracted in double.
  const std::vector<PackedLight> packed =
      pack_lights(lights, display.T_world_eye.position);
  if (!packed.empty()) slot.lights.write(packed.data(), packed.size() * sizeof(PackedLight));

  const VkDevice device = context_->device();
  constexpr VkImageLayout kRead = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  vk::write_image_descriptor(device, slot.set, kClientShadingBindingDepth, kSampled, gbuffer.depth.view(), kRead,
                             core_.sampler.get());
  vk::write_image_descriptor(device, slot.set, kClientShadingBindingNormal, kSampled, gbuffer.normal.view(), kRead,
                             core_.sampler.get());
  vk::write_image_descriptor(device, slot.set, kClientShadingBindingAlbedo, kSampled, gbuffer.albedo.view(), kRead,
                             core_.sampler.get());
  vk::write_image_descriptor(device, slot.set, kClientShadingBindingMask, kStorage, warp.mask.view(),
                             VK_IMAGE_LAYOUT_GENERAL);
  vk::write_image_descriptor(device, slot.set, kClientShadingBindingStatus, kStorage, warp.status.view(),
                             VK_IMAGE_LAYOUT_GENERAL);
  vk::write_image_descriptor(device, slot.set, kClientShadingBindingMotion, kStorage, warp.motion.view(),
                             VK_IMAGE_LAYOUT_GENERAL);
  vk::write_buffer_descriptor(device, slot.set, kClientShadingBindingLights, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                              slot.lights.handle());
  vk::write_image_descriptor(device, slot.set, kClientShadingBindingOutput, kStorage, output.view(),
                             VK_IMAGE_LAYOUT_GENERAL);
  vk::write_buffer_descriptor(device, slot.set, kClientShadingBindingLightSlots, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                              light_slot_table.handle());
  vk::write_image_descriptor(device, slot.set, kClientShadingBindingSoft, kStorage, warp.soft.view(),
                             VK_IMAGE_LAYOUT_GENERAL);

  for (vk::Image* image : {&gbuffer.depth, &gbuffer.normal, &gbuffer.albedo}) ensure_layout(cmd, *image, kRead);
  for (vk::Image* image : {&warp.mask, &warp.status, &warp.motion, &warp.soft}) {
    ensure_layout(cmd, *image, VK_IMAGE_LAYOUT_GENERAL);
  }
  discard_to_layout(cmd, output, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                    VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);

  ClientShadingPush push{};
  // Eye-relative rays in world axes, in double: p = (near / d) * (ray0 + (i + 0.5) ray_dx + (j + 0.5) ray_dy).
  const glm::dmat3 r = eye_to_world_rotation(display);
  const Tangents& t = display.tangents;
  const glm::dvec3 rays[3] = {r * glm::dvec3(t.left, t.up, -1.0), r * glm::dvec3(t.width() / extent.width, 0.0, 0.0),
                              r * glm::dvec3(0.0, -t.height() / extent.height, 0.0)};
  float* const outs[3] = {push.ray0, push.ray_dx, push.ray_dy};
  for (int k = 0; k < 3; ++k) {
    outs[k][0] = static_cast<float>(rays[k].x);
    outs[k][1] = static_cast<float>(rays[k].y);
    outs[k][2] = static_cast<float>(rays[k].z);
  }
  push.near_plane = static_cast<float>(near_plane);
  push.exposure = settings.exposure;
  push.background_r = settings.background.r;
  push.background_g = settings.background.g;
  push.background_b = settings.background.b;
  push.width = extent.width;
  push.height = extent.height;
  if (light_slots_) {  // fields are slots: their count and kinds; the grid's origin relative to this eye, in double
    bool soft[kMaxLights] = {};
    for (uint32_t f = 0; f < light_slots_->slot_count(); ++f) soft[f] = light_slots_->soft_slots()[f];
    push.light_count = light_slots_->slot_count();
    push.soft_lights = soft_light_mask(VisibilityLayout::for_lights(std::span<const bool>(soft, push.light_count)));
    for (int a = 0; a < 3; ++a) {
      push.slot_origin_mm[a] = static_cast<float>(static_cast<double>(light_slots_->origin_mm()[a]) -
                                                  display.T_world_eye.position[a] * 1000.0);
    }
  } else {
    push.light_count = static_cast<uint32_t>(packed.size());
    push.soft_lights = soft_light_mask(layout_for_lights(lights));
  }
  push.view_mode = static_cast<uint32_t>(settings.view);
  push.debug_light = std::min(settings.debug_light, 31u);
  push.flags = (settings.swap_red_blue ? kClientShadingSwapRedBlue : 0u) |
               (light_slots_ ? kClientShadingLightSlots : 0u) |
               (warp.soft_written && !light_slots_ ? kClientShadingSoftRefined : 0u);

  core_.dispatch(cmd, slot.set, &push, sizeof(push), extent.width, extent.height, kClientWarpGroupSize);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
                         VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                     VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
}

}  // namespace dhr::render
