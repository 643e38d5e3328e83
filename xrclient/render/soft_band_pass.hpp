// Band shares on the GPU (render/soft_bands.hpp): the table of a received buffer's refined soft fields, made by a
// compute pass (shaders/client/soft_bands.comp) instead of the CPU, with each upload of the buffer, in place after its
// masks. On the CPU the table cost 8.8 ms per 1984x1116 buffer (one core; docs/client.md, "Refined soft shares"); the
// pass is three dispatches over the table's cells: each cell's histogram of levels, its row's sums, its column's.
// Same definition and the same bytes as soft_band_table (tests/vulkan/client_soft_band_pass_test.cpp).
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "render/pass_util.hpp"
#include "render/soft_bands.hpp"
#include "vk/buffer.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

// What the pass reads and where it writes: a buffer's masks from word 0 of `visibility` (packed as
// VisibilityBuffer::data), its row validity (`rows`, bit r % 32 of word r / 32; only with `has_rows`), the table
// from word `share_word` on (soft_band_table's layout: table_words(shape) words).
struct SoftBandSource {
  const vk::Buffer* visibility = nullptr;
  const vk::Buffer* rows = nullptr;
  bool has_rows = false;
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t mask_bits = 0;  // 8, 16 or 32
  uint32_t share_word = 0;
};

class SoftBandPass;

// Band shares an upload makes (WarpSourceBuffers::upload): the fields with a bit in `bits` (soft_refine_bits of
// `layout`), recorded by `pass` (use `use`) into `cmd`.
struct SoftBandRequest {
  const VisibilityLayout* layout = nullptr;
  uint32_t bits = 0;
  SoftBandPass* pass = nullptr;
  uint32_t use = 0;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
};

class SoftBandPass {
 public:
  // `uses` independent uses, each with its own descriptor set and scratch buffer (the caller maps its frame slots and
  // sources onto them).
  SoftBandPass(const vk::Context& context, uint32_t uses);

  // The table's words for a shape (kClientSoftBandCellWords per cell).
  static uint64_t table_words(const SoftBandShape& shape);

  // Records the table of `source`'s soft fields with a bit in `bits` (soft_refine_bits of `layout`) at window radius
  // `radius` into source.visibility, use `use`; the writes are visible to later compute and fragment shader reads.
  // Earlier uses of `use` are done by the caller's slot contract. Throws std::invalid_argument for a use out of
  // range, a missing buffer, masks not 8, 16 or 32 bits wide, masks reaching past share_word, rows beyond the row
  // buffer's bits, a radius outside 1..kMaxSoftBandRadius or a table beyond the visibility buffer.
  void record(VkCommandBuffer cmd, uint32_t use, const SoftBandSource& source, const VisibilityLayout& layout,
              uint32_t bits, uint32_t radius);

 private:
  struct Use {
    VkDescriptorSet set = VK_NULL_HANDLE;
    vk::Buffer scratch;
  };
  const vk::Context* context_;
  ComputePassCore core_;
  std::vector<Use> uses_;
};

}  // namespace dhr::render
