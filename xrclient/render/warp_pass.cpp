#include "render/warp_pass.hpp"

#include <algorithm>
#include <array>
#include <glm/gtc/quaternion.hpp>
#include <stdexcept>
#include <string>

#include "log/log.hpp"
#include "dhr_shaders_client.hpp"
#include "render/pass_util.hpp"
#include "render/render_camera.hpp"
#include "shader_interface.h"
#include "vk/barriers.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace dhr::render {
namespace {

using namespace dhr::shader;  // binding numbers and flags shared with the GLSL

constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
constexpr VkDeviceSize kRowWords = kMaxBufferDimension / 32;
constexpr VkBufferUsageFlags kCounterUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

static_assert(kWarpStatusCount == kClientStatusCount && kClientStatusCount == 6, "two words of three fields");
static_assert(kClientCountBucketGroups * kClientWarpGroupSize * kClientWarpGroupSize <= 1023,
              "a bucket's count must fit a 10-bit field");

// Words of packed status counts for a display size: two per bucket (see kClientCountBucketGroups).
uint32_t count_words(Extent extent) {
  const uint32_t groups_x = (extent.width + kClientWarpGroupSize - 1) / kClientWarpGroupSize;
  const uint32_t groups_y = (extent.height + kClientWarpGroupSize - 1) / kClientWarpGroupSize;
  return 2 * ((groups_x + kClientCountBucketGroups - 1) / kClientCountBucketGroups) * groups_y;
}

// The per-status counts use subgroupAdd in compute shaders (Vulkan 1.1 subgroup arithmetic).
void require_subgroup_arithmetic(const vk::Context& context) {
  VkPhysicalDeviceSubgroupProperties subgroup{};
  subgroup.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
  VkPhysicalDeviceProperties2 properties{};
  properties.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  properties.pNext = &subgroup;
  vkGetPhysicalDeviceProperties2(context.physical_device(), &properties);
  constexpr VkSubgroupFeatureFlags kNeeded = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
  if ((subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) == 0 ||
      (subgroup.supportedOperations & kNeeded) != kNeeded || subgroup.subgroupSize > 128) {
    throw std::runtime_error("warp pass: the Vulkan device '" + context.info().name +
                             "' lacks subgroup arithmetic in compute shaders");
  }
}

void copy3(const glm::dvec3& v, float* out) {
  out[0] = static_cast<float>(v.x);
  out[1] = static_cast<float>(v.y);
  out[2] = static_cast<float>(v.z);
}

// Push constants, computed in double: everything is relative to the new eye, so only small numbers reach
// the GPU. `traced` is null without a usable visibility buffer.
ClientWarpPush make_push(const Camera& display, const Camera* traced, double near_plane) {
  ClientWarpPush push{};
  const Camera& old_camera = traced != nullptr ? *traced : display;
  const glm::dmat3 r_old_t = glm::transpose(eye_to_world_rotation(old_camera));
  const glm::dmat3 m = r_old_t * eye_to_world_rotation(display);  // new eye space -> old eye space
  const Tangents& nt = display.tangents;
  const double dx = nt.width() / display.extent.width;
  const double dy = -nt.height() / display.extent.height;
  copy3(m * glm::dvec3(nt.left, nt.up, -1.0), push.ray0);
  copy3(m * glm::dvec3(dx, 0.0, 0.0), push.ray_dx);
  copy3(m * glm::dvec3(0.0, dy, 0.0), push.ray_dy);
  copy3(r_old_t * (display.T_world_eye.position - old_camera.T_world_eye.position), push.trans);
  const Tangents& ot = old_camera.tangents;
  const double sx = old_camera.extent.width / ot.width();
  const double sy = old_camera.extent.height / ot.height();
  const double ox = -ot.left * sx, oy = ot.up * sy;
  push.old_px_scale = static_cast<float>(sx);
  push.old_px_offset = static_cast<float>(ox);
  push.old_py_scale = static_cast<float>(-sy);
  push.old_py_offset = static_cast<float>(oy);
  // Where pixel centre c would land with the new pose equal to the old one (motion = lookup - this).
  push.ident_px_scale = static_cast<float>(sx * dx);
  push.ident_px_offset = static_cast<float>(sx * nt.left + ox);
  push.ident_py_scale = static_cast<float>(-sy * dy);
  push.ident_py_offset = static_cast<float>(-sy * nt.up + oy);
  push.near_plane = static_cast<float>(near_plane);
  push.min_depth = static_cast<float>(kWarpMinDepth);
  push.width = display.extent.width;
  push.height = display.extent.height;
  // Without visibility the (clamped) lookups read the 4-byte placeholder buffer's first word.
  push.old_width = traced != nullptr ? traced->extent.width : 1u;
  push.old_height = traced != nullptr ? traced->extent.height : 1u;
  push.mask_bits = 32u;
  push.unknown_mask = 0xFFFFFFFFu;
  return push;
}

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
  return t;
}

WarpPass::WarpPass(const vk::Context& context, uint32_t slots) : context_(&context) {
  if (slots == 0) throw std::invalid_argument("WarpPass needs at least one slot");
  require_subgroup_arithmetic(context);
  const VkDevice device = context.device();
  const std::array<ComputeBinding, 7> bindings = {{
      {kClientWarpBindingDepth, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
      {kClientWarpBindingVisibility, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {kClientWarpBindingRowValid, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {kClientWarpBindingMask, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {kClientWarpBindingStatus, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {kClientWarpBindingMotion, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {kClientWarpBindingCounters, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
  }};
  core_ = ComputePassCore::create(device, bindings, sizeof(ClientWarpPush), "warp.comp", slots);
  slots_.resize(slots);
  for (Slot& s : slots_) {
    s.visibility = vk::Buffer(context, 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
    s.rows = vk::Buffer(context, kRowWords * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
    s.counters = vk::Buffer(context, 4, kCounterUsage, kHost);
    s.set = core_.allocate_set(device);
  }
}

void WarpPass::upload(Slot& slot, const VisibilityInput& visibility) {
  const VisibilityBuffer& buffer = *visibility.buffer;
  if (visibility.key != 0 && visibility.key == slot.key) return;
  const VkDeviceSize bytes = (buffer.size_bytes() + 3) / 4 * 4;
  if (bytes > slot.visibility.size()) {
    slot.visibility = vk::Buffer(*context_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
  }
  slot.visibility.write(buffer.data.data(), buffer.data.size());
  slot.key = visibility.key;
}

bool WarpPass::record(VkCommandBuffer cmd, uint32_t slot_index, vk::Image& depth, const Camera& display,
                            double near_plane, const VisibilityInput& visibility, WarpTargets& targets) {
  if (slot_index >= slots_.size()) throw std::invalid_argument("warp pass: slot out of range");
  const Extent extent = targets.extent();
  if (!(display.extent == extent) || depth.width() != extent.width || depth.height() != extent.height) {
    throw std::invalid_argument("warp pass: display camera, depth and targets differ in size");
  }
  Slot& slot = slots_[slot_index];
  slot.count_words = count_words(extent);
  if (VkDeviceSize{slot.count_words} * 4 > slot.counters.size()) {
    slot.counters = vk::Buffer(*context_, VkDeviceSize{slot.count_words} * 4, kCounterUsage, kHost);
  }

  bool usable = visibility.buffer != nullptr;
  if (usable) {
    if (auto err = validate_visibility_input(visibility.traced, *visibility.buffer, visibility.row_valid)) {
      log::warn("warp pass: ignoring the visibility input (%s)", err->c_str());
      usable = false;
    }
  }
  ClientWarpPush push = make_push(display, usable ? &visibility.traced : nullptr, near_plane);
  push.flags = (targets.has_motion() ? kClientWarpWriteMotion : 0u) |
               (targets.has_status() ? kClientWarpWriteStatus : 0u);
  if (usable) {
    push.unknown_mask = unknown_mask(visibility.buffer);
    push.mask_bits = static_cast<uint32_t>(visibility.buffer->mask_bits);
    upload(slot, visibility);
    push.flags |= kClientWarpHasVisibility;
    if (!visibility.row_valid.empty()) {
      std::array<uint32_t, kRowWords> words{};
      for (size_t r = 0; r < visibility.row_valid.size(); ++r) {
        if (visibility.row_valid[r] != 0) words[r / 32] |= 1u << (r % 32);
      }
      slot.rows.write(words.data(), words.size() * 4);
      push.flags |= kClientWarpHasRowValidity;
    }
  }

  const VkDevice device = context_->device();
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingDepth, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                             depth.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, core_.sampler.get());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingVisibility, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                              slot.visibility.handle());
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingRowValid, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                              slot.rows.handle());
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingMask, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                             targets.mask.view(), VK_IMAGE_LAYOUT_GENERAL);
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingStatus, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                             targets.status.view(), VK_IMAGE_LAYOUT_GENERAL);
  vk::write_image_descriptor(device, slot.set, kClientWarpBindingMotion, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                             targets.motion.view(), VK_IMAGE_LAYOUT_GENERAL);
  vk::write_buffer_descriptor(device, slot.set, kClientWarpBindingCounters, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                              slot.counters.handle());

  ensure_layout(cmd, depth, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  constexpr VkPipelineStageFlags2 kCs = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  discard_to_layout(cmd, targets.mask, VK_IMAGE_LAYOUT_GENERAL, kCs, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  for (const auto& [image, written] : {std::pair{&targets.status, targets.has_status()},
                                      std::pair{&targets.motion, targets.has_motion()}}) {
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

  core_.dispatch(cmd, slot.set, &push, sizeof(push), extent.width, extent.height, kClientWarpGroupSize);

  // Results feed the shading pass, transfers (readback, debug copies) and the host (counters).
  vk::memory_barrier(cmd, kCs, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     kCs | VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT | VK_PIPELINE_STAGE_2_HOST_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT |
                         VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_HOST_READ_BIT);
  return usable || visibility.buffer == nullptr;
}

WarpCounts WarpPass::read_counts(uint32_t slot_index) const {
  if (slot_index >= slots_.size()) throw std::invalid_argument("warp pass: slot out of range");
  const Slot& slot = slots_[slot_index];
  WarpCounts counts;
  // In chunks through a fixed array: no allocation per frame (thousands of buckets at headset sizes).
  std::array<uint32_t, 512> raw{};
  for (uint32_t first = 0; first < slot.count_words; first += static_cast<uint32_t>(raw.size())) {
    const uint32_t n = std::min<uint32_t>(static_cast<uint32_t>(raw.size()), slot.count_words - first);
    slot.counters.read(raw.data(), VkDeviceSize{n} * 4, VkDeviceSize{first} * 4);
    for (uint32_t i = 0; i < n; ++i) {
      // Even words hold statuses 0-2, odd words 3-5 (first is even: the chunk size is).
      for (uint32_t field = 0; field < 3; ++field) {
        counts.by_status[(i % 2) * 3 + field] += (raw[i] >> (10 * field)) & 1023u;
      }
    }
  }
  return counts;
}

}  // namespace dhr::render
