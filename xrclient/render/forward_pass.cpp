#include "render/forward_pass.hpp"

#include "render/soft_refine.hpp"
#include "render/warp_edges.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

#include "dhr_shaders_client.hpp"
#include "log/log.hpp"
#include "render/client_scene.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/light_layout.hpp"
#include "render/shadow_maps.hpp"
#include "scene/lighting.hpp"
#include "shaders/display_encode.h"
#include "shaders/shader_interface.h"
#include "vk/barriers.hpp"
#include "vk/context.hpp"
#include "vk/graphics_pipeline.hpp"
#include "vk/pipeline.hpp"

namespace dhr::render {
namespace {

using namespace dhr::shader;

constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
constexpr VkBufferUsageFlags kCounterUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
constexpr VkFormat kUintFormat = VK_FORMAT_R32_UINT;
constexpr VkFormat kStatusFormat = VK_FORMAT_R8_UINT;  // statuses 0-5: a byte per pixel to write and count

static_assert(static_cast<uint32_t>(ForwardMode::kLambert) == kClientForwardLambert);
static_assert(static_cast<uint32_t>(ForwardMode::kShadowMaps) == kClientForwardShadowMaps);
static_assert(static_cast<uint32_t>(ForwardMode::kPaperWarp) == kClientForwardPaperWarp);
static_assert(static_cast<uint32_t>(ForwardMode::kServerEdges) == kClientForwardServerEdges);

// Attachments: colour, then the status (the warp modes, and with the mask), then the mask (tests).
uint32_t attachment_count(const ForwardOptions& options) {
  return options.write_mask ? 3u : counts_status(options.mode) ? 2u : 1u;
}

}  // namespace

const char* to_string(ForwardMode mode) {
  switch (mode) {
    case ForwardMode::kLambert: return "lambert";
    case ForwardMode::kShadowMaps: return "shadow-maps";
    case ForwardMode::kPaperWarp: return "paper-warp";
    case ForwardMode::kServerEdges: return "server-edges";
  }
  return "?";
}

bool counts_status(ForwardMode mode) { return mode == ForwardMode::kPaperWarp || mode == ForwardMode::kServerEdges; }

void ForwardPass::set_mode(ForwardMode mode) {
  ForwardOptions next = options_;
  next.mode = mode;
  if (attachment_count(next) != attachment_count(options_)) {
    throw std::invalid_argument(std::string("forward pass: cannot switch from ") + to_string(options_.mode) + " to " +
                                to_string(mode) + " (other attachments)");
  }
  options_ = next;
}

ForwardTargets ForwardTargets::create(const vk::Context& context, Extent extent, const ForwardOptions& options) {
  constexpr VkImageUsageFlags kAttachment = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  ForwardTargets t;
  t.depth = vk::Image(context, extent.width, extent.height, kGBufferDepthFormat,
                      VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                          VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  t.colour = vk::Image(context, extent.width, extent.height, kShadingOutputFormat,
                       kAttachment | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
  const Extent status = attachment_count(options) >= 2 ? extent : Extent{1, 1};
  t.status = vk::Image(context, status.width, status.height, kStatusFormat, kAttachment | VK_IMAGE_USAGE_STORAGE_BIT);
  const Extent mask = options.write_mask ? extent : Extent{1, 1};
  t.mask = vk::Image(context, mask.width, mask.height, kUintFormat, kAttachment);
  return t;
}

ForwardPass::Slot::Slot(const vk::Context& context, size_t max_lights)
    : source(context),
      params(context, sizeof(ClientWarpParams), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost),
      moved(context, sizeof(ClientWarpMotion), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost),
      shadow_lights(context, kMaxLights * sizeof(ClientShadowLight), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost),
      lights(context, max_lights * sizeof(PackedLight), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost),
      shading(context, sizeof(ClientForwardShading), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost),
      counters(context, 4, kCounterUsage, kHost) {}

ForwardPass::ForwardPass(const vk::Context& context, const ClientScene& scene, const ForwardOptions& options)
    : context_(&context), scene_(&scene), options_(options), bands_(context, std::max(1u, options.slots)) {
  if (options.slots == 0) throw std::invalid_argument("ForwardPass needs at least one slot");
  require_subgroup_arithmetic(context, "forward pass");  // its count pass
  const VkDevice device = context.device();
  materials_ = MaterialSets(device, scene);
  constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  const std::array<std::pair<uint32_t, VkDescriptorType>, 10> frame_bindings = {{
      {kClientForwardBindingParams, kStorage},
      {kClientForwardBindingVisibility0, kStorage},
      {kClientForwardBindingRowValid0, kStorage},
      {kClientForwardBindingShadowMap, kSampled},
      {kClientForwardBindingShadowLights, kStorage},
      {kClientForwardBindingLights, kStorage},
      {kClientForwardBindingShading, kStorage},
      {kClientForwardBindingTracedDepth0, kSampled},
      {kClientForwardBindingMoved, kStorage},
      {kClientForwardBindingLightSlots, kStorage},
  }};
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  for (const auto& [binding, type] : frame_bindings) {
    bindings.push_back({binding, type, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr});
  }
  frame_layout_ = vk::create_descriptor_set_layout(device, bindings);
  const std::array<VkDescriptorPoolSize, 2> sizes = {{{kStorage, 7 * options.slots}, {kSampled, 2 * options.slots}}};
  frame_pool_ = vk::create_descriptor_pool(device, options.slots, sizes);
  const std::array<VkDescriptorSetLayout, 2> set_layouts = {materials_.layout(), frame_layout_.get()};
  const VkPushConstantRange push{kMaterialPushStages, 0, sizeof(ClientGBufferPush)};
  layout_ = vk::create_pipeline_layout(device, set_layouts, std::span(&push, 1));

  const auto modules = dhr_shaders_client_modules();
  // One shader variant per attachment count: each declares exactly the outputs it has attachments for.
  const std::array<VkFormat, 3> colour_formats = {kShadingOutputFormat, kStatusFormat, kUintFormat};
  const uint32_t attachments = attachment_count(options);
  const char* const shaders[] = {"forward.frag", "forward_status.frag", "forward_status_mask.frag"};
  vk::GraphicsPipelineDesc desc;
  desc.vertex = &vk::find_spirv(modules, "gbuffer.vert");
  desc.fragment = &vk::find_spirv(modules, shaders[attachments - 1]);
  desc.vertex_bindings = ClientScene::vertex_bindings();
  desc.vertex_attributes = ClientScene::vertex_attributes();
  desc.color_formats = std::span(colour_formats).first(attachments);
  desc.depth_format = kGBufferDepthFormat;
  desc.depth_compare = VK_COMPARE_OP_GREATER;
  desc.front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE;  // as the G-buffer pass
  desc.cull_mode = VK_CULL_MODE_BACK_BIT;
  cull_back_ = vk::create_graphics_pipeline(device, layout_.get(), desc);
  desc.cull_mode = VK_CULL_MODE_NONE;
  cull_none_ = vk::create_graphics_pipeline(device, layout_.get(), desc);
  sampler_ = create_nearest_sampler(device);

  const std::array<ComputeBinding, 2> count_bindings = {{{0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}, {1, kStorage}}};
  count_ = ComputePassCore::create(device, count_bindings, 12, "status_count.comp", options.slots);
  // With light slots (more than 32 lights) the Lambert mode shades every light by the slots' grid.
  const LightSlots& light_slots = scene.light_slots();
  const std::vector<uint32_t> table = light_slots.gpu_words(glm::dvec3(0.0));  // origin: per frame, relative to the eye
  light_slot_table_ = vk::create_buffer_with_data(context, std::span<const uint32_t>(table),
                                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  const size_t max_lights = std::max<size_t>({light_slots.light_count(), kMaxLights, 1});
  for (uint32_t i = 0; i < options.slots; ++i) {
    Slot& s = slots_.emplace_back(context, max_lights);
    s.set = vk::allocate_descriptor_set(device, frame_pool_.get(), frame_layout_.get());
    s.count_set = count_.allocate_set(device);
  }
  placeholder_atlas_ = vk::Image(context, 1, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT);
  context.submit_and_wait(
      [&](VkCommandBuffer cmd) { placeholder_atlas_.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL); });
}

ForwardPass::Recorded ForwardPass::record(VkCommandBuffer cmd, uint32_t slot_index, const ForwardFrame& frame,
                                          ForwardTargets& targets) {
  if (slot_index >= slots_.size()) throw std::invalid_argument("forward pass: slot out of range");
  const Extent extent = targets.extent();
  const Camera& display = frame.display;
  if (!(display.extent == extent) || targets.depth.width() != extent.width || targets.depth.height() != extent.height) {
    throw std::invalid_argument("forward pass: display camera and targets differ in size");
  }
  const ForwardMode mode = options_.mode;
  const uint32_t attachments = attachment_count(options_);
  if (attachments >= 2 && !targets.has_status()) throw std::invalid_argument("forward pass: no status target");
  if (options_.write_mask && !targets.has_mask()) throw std::invalid_argument("forward pass: no mask target");
  const LightSlots& light_slots = scene_->light_slots();
  const bool slotted = !light_slots.is_identity();
  if (slotted && mode != ForwardMode::kLambert)
    throw std::invalid_argument("forward pass: light slots (more than 32 lights) in the Lambert mode only");
  if (frame.lights.size() > (slotted ? light_slots.light_count() : kMaxLights))
    throw std::invalid_argument("forward pass: " + std::to_string(frame.lights.size()) + " lights, more than " +
                                (slotted ? "the scene's" : std::string("32")));
  if (frame.shading.view != ShadingView::kShaded) {
    throw std::invalid_argument("forward pass: debug views need the G-buffer pipeline");
  }
  const bool shadowed = mode == ForwardMode::kShadowMaps || mode == ForwardMode::kServerEdges;
  if (shadowed && frame.shadow_maps == nullptr) {
    throw std::invalid_argument(std::string("forward pass: ") + to_string(mode) + " mode without shadow maps");
  }
  Slot& slot = slots_[slot_index];

  Recorded out;
  const VisibilityInput* in = counts_status(mode) ? frame.visibility : nullptr;
  if (in != nullptr && in->buffer != nullptr) {
    if (auto err = validate_visibility_input(in->traced, *in->buffer, in->row_valid)) {
      log::warn("forward pass: ignoring the visibility input (%s)", err->c_str());
    } else {
      out.visibility_used = true;
    }
  }
  ClientWarpParams params = make_warp_params(display, out.visibility_used ? &in->traced : nullptr, frame.near_plane);
  for (size_t s = 0; s < kClientWarpSourceCount; ++s) params.source[s] = make_warp_source(display, s == 0 && out.visibility_used ? &in->traced : nullptr);
  // The warp's fields: the lights, or one light per slot (their count and kinds).
  const std::span<const SceneLight> fields = slotted ? std::span<const SceneLight>(scene_->field_lights()) : frame.lights;
  params.unknown_mask = unknown_mask(out.visibility_used ? in->buffer : nullptr, fields);
  const vk::Image* traced_depth = &placeholder_atlas_;
  const VisibilityLayout field_layout = layout_for_lights(fields);
  params.soft_lights = soft_light_mask(field_layout);  // the fields the bilinear vote blends
  params.soft_edge_lights = soft_edge_light_mask(fields);
  params.soft_refine_bits = soft_refine_bits(field_layout, params.soft_edge_lights);
  // Refined soft shares: the band shares of the refined fields follow the masks (and the edge band's marks).
  const bool refine = mode == ForwardMode::kServerEdges && frame.soft_refine && out.visibility_used && !slotted &&
                      params.soft_refine_bits != 0u;
  if (refine) params.flags |= kClientWarpSoftRefine;
  if (out.visibility_used) {
    const uint32_t edge_band = mode == ForwardMode::kServerEdges ? frame.edge_band : 0u;
    const SoftBandRequest shares{refine ? &field_layout : nullptr, refine ? params.soft_refine_bits : 0u, &bands_,
                                 slot_index, cmd};
    slot.source.upload(*context_, display, *in, params.source[0], edge_band, hard_field_bits(field_layout), &shares);
    if (mode == ForwardMode::kServerEdges && frame.traced_depth != nullptr) {
      const WarpSettings& test = frame.depth_test;
      const Extent depth_extent = depth_camera(in->traced, test.depth_scale).extent;
      if (frame.traced_depth->width() != depth_extent.width || frame.traced_depth->height() != depth_extent.height) {
        throw std::invalid_argument("forward pass: the traced depth differs in size from its traced camera's depth_camera");
      }
      traced_depth = frame.traced_depth;
      params.flags |= kClientWarpDepthTest;
      params.plane_tolerance_rel = static_cast<float>(test.plane_tolerance_rel);
      params.plane_tolerance_abs = static_cast<float>(test.plane_tolerance_abs);
      params.source[0].flags |= kClientSourceHasDepth;
      params.source[0].depth_scale = test.depth_scale;
    }
    if (mode == ForwardMode::kServerEdges && frame.motion != nullptr) params.flags |= kClientWarpMotion;
  }
  const vk::Image* atlas = &placeholder_atlas_;
  if (shadowed) {
    std::array<ClientShadowLight, kMaxLights> shadow_lights{};
    try {
      describe_shadow_maps(*frame.shadow_maps, frame.lights, display, params, shadow_lights);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("forward pass: ") + e.what());
    }
    if (!frame.lights.empty()) slot.shadow_lights.write(shadow_lights.data(), frame.lights.size() * sizeof(ClientShadowLight));
    atlas = &frame.shadow_maps->atlas();
  }
  const std::vector<PackedLight> packed = pack_lights(frame.lights, display.T_world_eye.position);
  if (!packed.empty()) slot.lights.write(packed.data(), packed.size() * sizeof(PackedLight));
  params.light_count = static_cast<uint32_t>(fields.size());
  slot.params.write(&params, sizeof(params));
  const ClientWarpMotion no_motion{};
  slot.moved.write((params.flags & kClientWarpMotion) != 0u ? frame.motion : &no_motion, sizeof(ClientWarpMotion));
  ClientForwardShading shading{};
  shading.exposure = frame.shading.exposure;
  shading.mode = static_cast<uint32_t>(mode);
  shading.flags = frame.shading.swap_red_blue ? kClientShadingSwapRedBlue : 0u;
  if (slotted) {  // fields are slots: their count and kinds, the grid's origin relative to this eye (in double)
    bool soft[kMaxLights] = {};
    for (uint32_t f = 0; f < light_slots.slot_count(); ++f) soft[f] = light_slots.soft_slots()[f];
    shading.flags |= kClientShadingLightSlots;
    shading.light_count = light_slots.slot_count();
    shading.soft_lights = soft_light_mask(VisibilityLayout::for_lights(std::span<const bool>(soft, shading.light_count)));
    for (int a = 0; a < 3; ++a) {
      shading.slot_origin_mm[a] = static_cast<float>(static_cast<double>(light_slots.origin_mm()[a]) -
                                                     display.T_world_eye.position[a] * 1000.0);
    }
  } else {
    shading.light_count = static_cast<uint32_t>(packed.size());
    shading.soft_lights = soft_light_mask(layout_for_lights(frame.lights));
  }
  slot.shading.write(&shading, sizeof(shading));

  const VkDevice device = context_->device();
  constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  vk::write_buffer_descriptor(device, slot.set, kClientForwardBindingParams, kStorage, slot.params.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientForwardBindingVisibility0, kStorage,
                              slot.source.visibility.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientForwardBindingRowValid0, kStorage, slot.source.rows.handle());
  vk::write_image_descriptor(device, slot.set, kClientForwardBindingShadowMap, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                             atlas->view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, sampler_.get());
  vk::write_buffer_descriptor(device, slot.set, kClientForwardBindingShadowLights, kStorage,
                              slot.shadow_lights.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientForwardBindingLights, kStorage, slot.lights.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientForwardBindingShading, kStorage, slot.shading.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientForwardBindingLightSlots, kStorage, light_slot_table_.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientForwardBindingMoved, kStorage, slot.moved.handle());
  vk::write_image_descriptor(device, slot.set, kClientForwardBindingTracedDepth0,
                             VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, traced_depth->view(),
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, sampler_.get());

  const bool counting = counts_status(mode);
  slot.counted = counting;
  if (counting) {
    slot.count_words = warp_count_words(extent);
    if (VkDeviceSize{slot.count_words} * 4 > slot.counters.size()) {
      slot.counters = vk::Buffer(*context_, VkDeviceSize{slot.count_words} * 4, kCounterUsage, kHost);
    }
    // The counters start at zero; earlier readers (the host, after the previous use) are done by contract.
    vkCmdFillBuffer(cmd, slot.counters.handle(), 0, VkDeviceSize{slot.count_words} * 4, 0);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                       VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  }

  discard_to_layout(cmd, targets.depth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  const bool with_status = attachments >= 2;
  const bool with_mask = attachments >= 3;
  for (const auto& [image, used] : {std::pair{&targets.colour, true}, std::pair{&targets.status, with_status},
                                   std::pair{&targets.mask, with_mask}}) {
    if (used) {
      discard_to_layout(cmd, *image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    }
  }
  VkClearValue background{};
  {
    namespace de = dhr::display_encode;
    const glm::vec3 bg = frame.shading.background;
    glm::vec3 c(de::srgb_encode(bg.x), de::srgb_encode(bg.y), de::srgb_encode(bg.z));
    if (frame.shading.swap_red_blue) std::swap(c.x, c.z);
    background.color = {{c.x, c.y, c.z, 1.0f}};
  }
  VkClearValue status_clear{};
  status_clear.color.uint32[0] = kClientStatusBackground;
  VkClearValue unknown{};  // the mask where nothing is drawn, as the compute warp writes it for background
  unknown.color.uint32[0] = params.unknown_mask;
  const std::array<VkRenderingAttachmentInfo, 3> colour = {
      cleared_attachment(targets.colour.view(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, background),
      cleared_attachment(targets.status.view(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, status_clear),
      cleared_attachment(targets.mask.view(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, unknown)};
  VkClearValue depth_clear{};
  depth_clear.depthStencil = {0.0f, 0};  // reversed-Z: 0 is infinitely far
  const VkRenderingAttachmentInfo depth =
      cleared_attachment(targets.depth.view(), VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, depth_clear);
  begin_rendering(cmd, extent.width, extent.height, std::span(colour).first(attachments), &depth);
  vk::set_viewport_and_scissor(cmd, {extent.width, extent.height});
  const VkDescriptorSet frame_set = slot.set;
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 1, 1, &frame_set, 0, nullptr);
  out.draws = record_scene_draws(cmd, *scene_, materials_, {layout_.get(), cull_back_.get(), cull_none_.get()}, display,
                                 frame.near_plane, frame.moved);
  vkCmdEndRendering(cmd);

  targets.depth.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  targets.colour.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
  if (with_status) targets.status.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
  if (with_mask) targets.mask.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
  if (counting) {
    vk::write_image_descriptor(device, slot.count_set, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, targets.status.view(),
                               VK_IMAGE_LAYOUT_GENERAL);
    vk::write_buffer_descriptor(device, slot.count_set, 1, kStorage, slot.counters.handle());
    const std::array<uint32_t, 3> push = {extent.width, extent.height, mode == ForwardMode::kServerEdges ? 1u : 0u};
    count_.dispatch(cmd, slot.count_set, push.data(), sizeof(push), extent.width, extent.height, kClientWarpGroupSize);
  }
  // Results feed the sink's copies, later shaders and the host (counters).
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
                         VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT | VK_PIPELINE_STAGE_2_HOST_BIT,
                     VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_HOST_READ_BIT);
  return out;
}

WarpCounts ForwardPass::read_counts(uint32_t slot_index) const {
  if (slot_index >= slots_.size()) throw std::invalid_argument("forward pass: slot out of range");
  const Slot& slot = slots_[slot_index];
  if (!slot.counted) return WarpCounts{};
  return unpack_warp_counts(slot.counters, slot.count_words);
}

}  // namespace dhr::render
