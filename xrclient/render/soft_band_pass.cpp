#include "render/soft_band_pass.hpp"

#include <array>
#include <bit>
#include <stdexcept>
#include <string>

#include "shaders/shader_interface.h"
#include "vk/barriers.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace dhr::render {

using shader::ClientSoftBandPush;

SoftBandPass::SoftBandPass(const vk::Context& context, uint32_t uses) : context_(&context) {
  if (uses == 0) throw std::invalid_argument("SoftBandPass: zero uses");
  constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  const std::array<ComputeBinding, 3> bindings = {{{shader::kClientSoftBandBindingVisibility, kStorage},
                                                   {shader::kClientSoftBandBindingRows, kStorage},
                                                   {shader::kClientSoftBandBindingScratch, kStorage}}};
  core_ = ComputePassCore::create(context.device(), bindings, sizeof(ClientSoftBandPush), "soft_bands.comp", uses);
  uses_.resize(uses);
  for (Use& u : uses_) u.set = core_.allocate_set(context.device());
}

uint64_t SoftBandPass::table_words(const SoftBandShape& shape) {
  return uint64_t{shape.columns} * shape.rows * shader::kClientSoftBandCellWords;
}

void SoftBandPass::record(VkCommandBuffer cmd, uint32_t use, const SoftBandSource& source,
                          const VisibilityLayout& layout, uint32_t bits, uint32_t radius) {
  if (use >= uses_.size()) throw std::invalid_argument("SoftBandPass: use out of range");
  if (source.visibility == nullptr || source.rows == nullptr) throw std::invalid_argument("SoftBandPass: no buffer");
  if (source.mask_bits != 8 && source.mask_bits != 16 && source.mask_bits != 32) {
    throw std::invalid_argument("SoftBandPass: masks of " + std::to_string(source.mask_bits) + " bits");
  }
  if (uint64_t{source.width} * source.height * source.mask_bits / 8 > uint64_t{source.share_word} * 4 ||
      (source.has_rows && uint64_t{source.rows->size()} * 8 < source.height)) {
    throw std::invalid_argument("SoftBandPass: the masks or the rows do not fit their buffers before the table");
  }
  const SoftBandShape shape = soft_band_shape(source.width, source.height, radius);
  const uint64_t cells = uint64_t{shape.columns} * shape.rows;
  if ((uint64_t{source.share_word} + table_words(shape)) * 4 > source.visibility->size()) {
    throw std::invalid_argument("SoftBandPass: the table (" + std::to_string(table_words(shape)) +
                                " words from word " + std::to_string(source.share_word) +
                                ") does not fit the visibility buffer");
  }
  ClientSoftBandPush push{};
  push.width = source.width;
  push.height = source.height;
  push.mask_bits = source.mask_bits;
  push.cell_shift = static_cast<uint32_t>(std::countr_zero(shape.cell));
  push.columns = shape.columns;
  push.rows = shape.rows;
  push.reach = shape.reach;
  push.has_rows = source.has_rows ? 1u : 0u;
  push.share_word = source.share_word;
  push.sum_word = static_cast<uint32_t>(cells * shader::kClientSoftBandCountWords);
  uint32_t rank = 0;
  for (uint32_t i = 0; i < layout.light_count && rank < shader::kClientSoftRefineFields; ++i) {
    if (!layout.is_soft(i)) continue;
    const uint32_t field = ((1u << layout.bits[i]) - 1u) << layout.offset[i];
    if ((bits & field) != 0) {
      push.refined |= 1u << rank;
      push.field_offset[rank] = layout.offset[i];
    }
    ++rank;
  }

  Use& u = uses_[use];
  const VkDeviceSize scratch_bytes = cells * (shader::kClientSoftBandCountWords + shader::kClientSoftBandLaneWords) * 4;
  if (u.scratch.size() < scratch_bytes) {
    u.scratch = vk::Buffer(*context_, scratch_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                           VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  }
  const VkDevice device = context_->device();
  constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  vk::write_buffer_descriptor(device, u.set, shader::kClientSoftBandBindingVisibility, kStorage,
                              source.visibility->handle());
  vk::write_buffer_descriptor(device, u.set, shader::kClientSoftBandBindingRows, kStorage, source.rows->handle());
  vk::write_buffer_descriptor(device, u.set, shader::kClientSoftBandBindingScratch, kStorage, u.scratch.handle());

  constexpr VkPipelineStageFlags2 kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  constexpr VkAccessFlags2 kReadWrite = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
  // The masks are host writes made before the submission; earlier uses of this scratch are done (the slot contract).
  for (const uint32_t stage : {shader::kClientSoftBandCount, shader::kClientSoftBandRowSum,
                               shader::kClientSoftBandShares}) {
    // Each stage reads what the one before wrote.
    if (stage != shader::kClientSoftBandCount) vk::memory_barrier(cmd, kCompute, kReadWrite, kCompute, kReadWrite);
    push.stage = stage;
    core_.dispatch(cmd, u.set, &push, sizeof(push), shape.columns, shape.rows, shader::kClientWarpGroupSize);
  }
  vk::memory_barrier(cmd, kCompute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     kCompute | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

}  // namespace dhr::render
