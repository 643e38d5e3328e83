#include "render/warp_pass.hpp"

#include "render/soft_refine.hpp"
#include "render/warp_edges.hpp"

#include "render/light_layout.hpp"

#include <algorithm>
#include <array>
#include <glm/gtc/quaternion.hpp>
#include <stdexcept>
#include <string>

#include "log/log.hpp"
#include "dhr_shaders_client.hpp"
#include "render/pass_util.hpp"
#include "render/render_camera.hpp"
#include "render/shadow_maps.hpp"
#include "render/warp_params.hpp"
#include "scene/lighting.hpp"
#include "shaders/shader_interface.h"
#include "vk/barriers.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace dhr::render {
namespace {

using namespace dhr::shader;  // binding numbers and flags shared with the GLSL

constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
constexpr VkBufferUsageFlags kCounterUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

static_assert(kWarpStatusCount == kClientStatusCount, "WarpStatus mirrors kClientStatus*");
static_assert(kClientCountWords * 3 >= kClientCountFields, "three 10-bit fields per word");
static_assert(kClientCountBucketGroups * kClientWarpGroupSize * kClientWarpGroupSize <= 1023,
              "a bucket's count must fit a 10-bit field");

}  // namespace

WarpTargets WarpTargets::create(const vk::Context& context, Extent extent, WarpOutputs outputs) {
  constexpr VkImageUsageFlags kUsage =
      VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  WarpTargets t;
  t.mask = vk::Image(context, extent.width, extent.height, VK_FORMAT_R32_UINT, kUsage);
  const Extent status = outputs.status ? extent : Extent{1, 1};
  t.status = vk::Image(context, status.width, status.height, VK_FORMAT_R32_UINT, kUsage);
  const Extent motion = outputs.motion ? extent : Extent{1, 1};
  t.motion = vk::Image(context, motion.width, motion.height, VK_FORMAT_R32G32_SFLOAT, kUsage);
  const Extent soft = outputs.soft ? extent : Extent{1, 1};
  t.soft = vk::Image(context, soft.width, soft.height, VK_FORMAT_R32_UINT, kUsage);
  return t;
}

WarpPass::WarpPass(const vk::Context& context, uint32_t slots)
    : context_(&context), bands_(context, std::max(1u, slots) * kClientWarpSourceCount) {
  if (slots == 0) throw std::invalid_argument("WarpPass needs at least one slot");
  require_subgroup_arithmetic(context, "warp pass");
  const VkDevice device = context.device();
  constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  constexpr VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  const std::array<ComputeBinding, 21> bindings = {{
      {kClientWarpBindingDepth, kSampled},
      {kClientWarpBindingVisibility0, kStorage},
      {kClientWarpBindingRowValid0, kStorage},
      {kClientWarpBindingMask, kImage},
      {kClientWarpBindingStatus, kImage},
      {kClientWarpBindingMotion, kImage},
      {kClientWarpBindingCounters, kStorage},
      {kClientWarpBindingNormal, kSampled},
      {kClientWarpBindingOldDepth0, kSampled},
      {kClientWarpBindingVisibility1, kStorage},
      {kClientWarpBindingRowValid1, kStorage},
      {kClientWarpBindingOldDepth1, kSampled},
      {kClientWarpBindingParams, kStorage},
      {kClientWarpBindingShadowMap, kSampled},
      {kClientWarpBindingShadowLights, kStorage},
      {kClientWarpBindingLights, kStorage},
      {kClientWarpBindingVisibility2, kStorage},
      {kClientWarpBindingRowValid2, kStorage},
      {kClientWarpBindingOldDepth2, kSampled},
      {kClientWarpBindingMoved, kStorage},
      {kClientWarpBindingSoft, kImage},
  }};
  // The shader reads everything from the parameter buffer; the push range carries nothing it uses.
  core_ = ComputePassCore::create(device, bindings, 4, "warp.comp", slots);
  slots_.resize(slots);
  for (Slot& s : slots_) {
    for (uint32_t i = 0; i < kClientWarpSourceCount; ++i) s.sources.emplace_back(context);
    s.params = vk::Buffer(context, sizeof(ClientWarpParams), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
    s.moved = vk::Buffer(context, sizeof(ClientWarpMotion), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
    s.shadow_lights = vk::Buffer(context, kMaxLights * sizeof(ClientShadowLight), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
    s.lights = vk::Buffer(context, kMaxLights * sizeof(PackedLight), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
    s.counters = vk::Buffer(context, 4, kCounterUsage, kHost);
    s.set = core_.allocate_set(device);
  }
  placeholder_depth_ = vk::Image(context, 1, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT);
  placeholder_normal_ = vk::Image(context, 1, 1, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT);
  context.submit_and_wait([&](VkCommandBuffer cmd) {
    placeholder_depth_.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    placeholder_normal_.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  });
}

bool WarpPass::record(VkCommandBuffer cmd, uint32_t slot_index, const WarpFrame& frame, WarpTargets& targets) {
  if (slot_index >= slots_.size()) throw std::invalid_argument("warp pass: slot out of range");
  if (frame.depth == nullptr) throw std::invalid_argument("warp pass: no depth image");
  const Extent extent = targets.extent();
  vk::Image& depth = *frame.depth;
  const Camera& display = frame.display;
  if (!(display.extent == extent) || depth.width() != extent.width || depth.height() != extent.height) {
    throw std::invalid_argument("warp pass: display camera, depth and targets differ in size");
  }
  const WarpSettings& settings = frame.settings;
  const bool shadows = settings.uses_shadow_maps();
  if (shadows && frame.shadow_maps == nullptr) {
    throw std::invalid_argument("warp pass: shadow settings without shadow maps");
  }
  const bool needs_normal = settings.depth_test || shadows;
  if (needs_normal && (frame.normal == nullptr || frame.normal->width() != extent.width ||
                       frame.normal->height() != extent.height)) {
    throw std::invalid_argument("warp pass: the depth test and shadow lookups need the display normals");
  }
  Slot& slot = slots_[slot_index];
  slot.count_words = warp_count_words(extent);
  if (VkDeviceSize{slot.count_words} * 4 > slot.counters.size()) {
    slot.counters = vk::Buffer(*context_, VkDeviceSize{slot.count_words} * 4, kCounterUsage, kHost);
  }

  // Which sources are usable.
  std::array<bool, kClientWarpSourceCount> usable{};
  for (size_t s = 0; s < usable.size(); ++s) {
    const VisibilityInput* in = frame.sources[s].visibility;
    if (s == 1 && !settings.other_eye) continue;
    if (s == 2 && !settings.older_buffer) continue;
    if (in == nullptr || in->buffer == nullptr) continue;
    if (auto err = validate_visibility_input(in->traced, *in->buffer, in->row_valid)) {
      log::warn("warp pass: ignoring the visibility input of source %zu (%s)", s, err->c_str());
      continue;
    }
    usable[s] = true;
  }
  const VisibilityInput* own = frame.sources[0].visibility;
  ClientWarpParams params = make_warp_params(display, usable[0] ? &own->traced : nullptr, frame.near_plane);
  params.flags = (targets.has_motion() ? kClientWarpWriteMotion : 0u) |
                 (targets.has_status() ? kClientWarpWriteStatus : 0u) |
                 (settings.bilinear ? kClientWarpBilinear : 0u) | (settings.depth_test ? kClientWarpDepthTest : 0u) |
                 (settings.shadow_fill ? kClientWarpShadowFill : 0u) |
                 (settings.shadow_edges ? kClientWarpShadowEdges : 0u) |
                 (settings.shadow_first ? kClientWarpShadowFirst : 0u) |
                 (settings.older_buffer ? kClientWarpOlderBuffer : 0u) |
                 (settings.neighbour_fill ? kClientWarpNeighbourFill : 0u) |
                 (settings.motion ? kClientWarpMotion : 0u);
  params.plane_tolerance_rel = static_cast<float>(settings.plane_tolerance_rel);
  params.plane_tolerance_abs = static_cast<float>(settings.plane_tolerance_abs);
  std::array<vk::Image*, kClientWarpSourceCount> old_depth{&placeholder_depth_, &placeholder_depth_,
                                                           &placeholder_depth_};
  // The fields the bilinear vote blends (describe_shadow_maps sets the same light count with the maps); the edge
  // band marks the others.
  params.light_count = static_cast<uint32_t>(std::min<size_t>(frame.lights.size(), kMaxLights));
  const VisibilityLayout layout = layout_for_lights(frame.lights.first(params.light_count));
  params.soft_lights = soft_light_mask(layout);
  params.soft_edge_lights = soft_edge_light_mask(frame.lights.first(params.light_count));
  // Refined soft shares: bilinear lookups of a layout with soft fields, into the soft target.
  params.soft_refine_bits = soft_refine_bits(layout, params.soft_edge_lights);
  targets.soft_written =
      settings.soft_refine && settings.bilinear && params.soft_refine_bits != 0u && targets.has_soft();
  if (targets.soft_written) params.flags |= kClientWarpSoftRefine;
  const uint32_t edge_band = settings.bilinear ? settings.edge_band : 0u;
  for (size_t s = 0; s < usable.size(); ++s) {
    const VisibilityInput* in = frame.sources[s].visibility;
    params.source[s] = make_warp_source(display, usable[s] ? &in->traced : nullptr);
    if (!usable[s]) continue;
    const SoftBandRequest shares{targets.soft_written ? &layout : nullptr, params.soft_refine_bits, &bands_,
                                 slot_index * kClientWarpSourceCount + static_cast<uint32_t>(s), cmd};
    slot.sources[s].upload(*context_, display, *in, params.source[s], edge_band, hard_field_bits(layout), &shares);
    vk::Image* traced_depth = frame.sources[s].traced_depth;
    if (traced_depth != nullptr) {
      const Extent depth_extent = depth_camera(in->traced, settings.depth_scale).extent;
      if (traced_depth->width() != depth_extent.width || traced_depth->height() != depth_extent.height) {
        throw std::invalid_argument("warp pass: a traced depth differs in size from its traced camera's depth_camera");
      }
      old_depth[s] = traced_depth;
      params.source[s].flags |= kClientSourceHasDepth;
      params.source[s].depth_scale = settings.depth_scale;
    }
  }
  params.unknown_mask = unknown_mask(usable[0] ? own->buffer : nullptr, frame.lights);

  const vk::Image* atlas = &placeholder_depth_;
  if (shadows) {
    const ShadowMaps& maps = *frame.shadow_maps;
    std::array<ClientShadowLight, kMaxLights> shadow_lights{};
    try {
      describe_shadow_maps(maps, frame.lights, display, params, shadow_lights);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("warp pass: ") + e.what());
    }
    slot.shadow_lights.write(shadow_lights.data(), frame.lights.size() * sizeof(ClientShadowLight));
    const std::vector<PackedLight> packed = pack_lights(frame.lights, display.T_world_eye.position);
    if (!packed.empty()) slot.lights.write(packed.data(), packed.size() * sizeof(PackedLight));
    atlas = &maps.atlas();
  }
  slot.params.write(&params, sizeof(params));
  // The motion rule's data (kClientWarpMotion); disabled (all zero) without it.
  const ClientWarpMotion no_motion{};
  const ClientWarpMotion& moved = settings.motion && frame.motion != nullptr ? *frame.motion : no_motion;
  slot.moved.write(&moved, sizeof(moved));

  const VkDevice device = context_->device();
  const VkSampler sampler = core_.sampler.get();
  constexpr VkImageLayout kRead = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingDepth, kSampled, depth.view(), kRead, sampler);
  const vk::Image& normal = needs_normal ? *frame.normal : placeholder_normal_;
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingNormal, kSampled, normal.view(), kRead, sampler);
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingOldDepth0, kSampled, old_depth[0]->view(), kRead,
                             sampler);
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingOldDepth1, kSampled, old_depth[1]->view(), kRead,
                             sampler);
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingOldDepth2, kSampled, old_depth[2]->view(), kRead,
                             sampler);
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingShadowMap, kSampled, atlas->view(), kRead, sampler);
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingVisibility0, kStorage,
                              slot.sources[0].visibility.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingRowValid0, kStorage, slot.sources[0].rows.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingVisibility1, kStorage,
                              slot.sources[1].visibility.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingRowValid1, kStorage, slot.sources[1].rows.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingVisibility2, kStorage,
                              slot.sources[2].visibility.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingRowValid2, kStorage, slot.sources[2].rows.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingMoved, kStorage, slot.moved.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingParams, kStorage, slot.params.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingShadowLights, kStorage,
                              slot.shadow_lights.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingLights, kStorage, slot.lights.handle());
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingMask, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                             targets.mask.view(), VK_IMAGE_LAYOUT_GENERAL);
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingStatus, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                             targets.status.view(), VK_IMAGE_LAYOUT_GENERAL);
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingMotion, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                             targets.motion.view(), VK_IMAGE_LAYOUT_GENERAL);
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingSoft, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                             targets.soft.view(), VK_IMAGE_LAYOUT_GENERAL);
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingCounters, kStorage, slot.counters.handle());

  ensure_layout(cmd, depth, kRead);
  if (needs_normal) ensure_layout(cmd, *frame.normal, kRead);
  for (vk::Image* image : old_depth) ensure_layout(cmd, *image, kRead);
  constexpr VkPipelineStageFlags2 kCs = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  discard_to_layout(cmd, targets.mask, VK_IMAGE_LAYOUT_GENERAL, kCs, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  for (const auto& [image, written] : {std::pair{&targets.status, targets.has_status()},
                                      std::pair{&targets.motion, targets.has_motion()},
                                      std::pair{&targets.soft, targets.soft_written}}) {
    if (written) {
      discard_to_layout(cmd, *image, VK_IMAGE_LAYOUT_GENERAL, kCs, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    } else {
      ensure_layout(cmd, *image, VK_IMAGE_LAYOUT_GENERAL);
    }
  }
  // The counters start at zero; earlier readers (the host, after the previous use) are done by contract.
  vkCmdFillBuffer(cmd, slot.counters.handle(), 0, VkDeviceSize{slot.count_words} * 4, 0);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, kCs,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);

  const uint32_t no_push = 0;
  core_.dispatch(cmd, slot.set, &no_push, sizeof(no_push), extent.width, extent.height, kClientWarpGroupSize);

  // Results feed the shading pass, transfers (readback, debug copies) and the host (counters).
  vk::memory_barrier(cmd, kCs, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     kCs | VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT | VK_PIPELINE_STAGE_2_HOST_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT |
                         VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_HOST_READ_BIT);
  return usable[0] || own == nullptr || own->buffer == nullptr;
}

WarpCounts WarpPass::read_counts(uint32_t slot_index) const {
  if (slot_index >= slots_.size()) throw std::invalid_argument("warp pass: slot out of range");
  const Slot& slot = slots_[slot_index];
  return unpack_warp_counts(slot.counters, slot.count_words);
}

}  // namespace dhr::render
