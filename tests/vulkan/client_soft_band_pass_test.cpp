// Band shares on the GPU (render/soft_band_pass.hpp) against the CPU's soft_band_table: the same bytes, word for
// word, for cells of 2, 4, 8 and 16 pixels, masks of 8, 16 and 32 bits, missing rows, fields left out, more soft
// fields than are refined, and the widest window (whose counts fill most of the 16-bit lanes); and an upload that
// makes the table again where an earlier one's command buffer was never submitted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <vector>

#include "render/soft_band_pass.hpp"
#include "render/soft_bands.hpp"
#include "render/soft_refine.hpp"
#include "render/warp_params.hpp"
#include "shaders/shader_interface.h"
#include "vk/buffer.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using SoftBandPassTest = vk::test::VulkanTest;

constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;

struct Case {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<int> soft;      // the layout's lights: 1 soft, 0 hard
  uint32_t radius = 0;
  uint32_t edge_lights = 0;   // soft_refine_bits leaves their fields out
  bool missing_rows = false;
};

// Per soft field a smooth share (a slanted ramp, another slope per field) plus noise, a flat region at the top and
// bottom levels and a contact shadow (a jump of several levels); hard fields random.
VisibilityBuffer make_buffer(const Case& c, const VisibilityLayout& layout) {
  std::mt19937 rng(c.width * 7919u + c.height);
  std::uniform_real_distribution<float> noise(-0.08f, 0.08f);
  VisibilityBuffer b = VisibilityBuffer::create(c.width, c.height, layout.total_bits());
  for (uint32_t y = 0; y < c.height; ++y) {
    for (uint32_t x = 0; x < c.width; ++x) {
      uint32_t mask = 0;
      for (uint32_t i = 0; i < layout.light_count; ++i) {
        float share = std::fmod((x * (1.0f + 0.3f * i) + y * (0.5f + 0.2f * i)) / (20.0f * (i + 1)), 1.4f) - 0.2f;
        if (x > c.width / 2 && x < c.width / 2 + 9) share -= 0.6f;  // a contact shadow's jump
        share = std::clamp(share + noise(rng), 0.0f, 1.0f);
        mask = layout.with_visibility(mask, i, layout.is_soft(i) ? share : (rng() & 1u ? 1.0f : 0.0f));
      }
      b.set(x, y, mask);
    }
  }
  return b;
}

// The table the GPU pass makes, read back.
std::vector<uint32_t> gpu_table(vk::Context& ctx, const VisibilityBuffer& b, std::span<const uint8_t> row_valid,
                                const VisibilityLayout& layout, uint32_t bits, uint32_t radius) {
  const SoftBandShape shape = soft_band_shape(b.width, b.height, radius);
  const VkDeviceSize mask_bytes = (b.size_bytes() + 3) / 4 * 4;
  const uint64_t words = SoftBandPass::table_words(shape);
  vk::Buffer visibility(ctx, mask_bytes + words * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
  visibility.write(b.data.data(), b.data.size());
  const std::vector<uint32_t> poison(words, 0x5A5A5A5Au);  // every word must be written
  visibility.write(poison.data(), words * 4, mask_bytes);
  std::vector<uint32_t> row_words(kMaxBufferDimension / 32, 0u);
  for (size_t r = 0; r < row_valid.size(); ++r) {
    if (row_valid[r] != 0) row_words[r / 32] |= 1u << (r % 32);
  }
  vk::Buffer rows(ctx, row_words.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
  rows.write(row_words.data(), row_words.size() * 4);

  SoftBandPass pass(ctx, 1);
  SoftBandSource source;
  source.visibility = &visibility;
  source.rows = &rows;
  source.has_rows = !row_valid.empty();
  source.width = b.width;
  source.height = b.height;
  source.mask_bits = static_cast<uint32_t>(b.mask_bits);
  source.share_word = static_cast<uint32_t>(mask_bytes / 4);
  ctx.submit_and_wait([&](VkCommandBuffer cmd) { pass.record(cmd, 0, source, layout, bits, radius); });
  std::vector<uint32_t> out(words);
  visibility.read(out.data(), words * 4, mask_bytes);
  return out;
}

VisibilityLayout layout_of(const std::vector<int>& soft) {
  bool lights[32] = {};
  std::copy(soft.begin(), soft.end(), lights);
  return VisibilityLayout::for_lights(std::span<const bool>(lights, soft.size()));
}

void expect_same_table(vk::Context& ctx, const Case& c) {
  const VisibilityLayout layout = layout_of(c.soft);
  const VisibilityBuffer b = make_buffer(c, layout);
  std::vector<uint8_t> row_valid;
  if (c.missing_rows) {
    row_valid.assign(c.height, 1);
    for (uint32_t y = 3; y < c.height; y += 11) row_valid[y] = 0;
    for (uint32_t y = c.height / 3; y < c.height / 3 + 40 && y < c.height; ++y) row_valid[y] = 0;  // a lost shard
  }
  const uint32_t bits = soft_refine_bits(layout, c.edge_lights);
  const SoftBandTable cpu = soft_band_table(layout, b, row_valid, bits, c.radius);
  const std::vector<uint32_t> gpu = gpu_table(ctx, b, row_valid, layout, bits, c.radius);
  ASSERT_EQ(gpu.size(), cpu.words.size());
  size_t differ = 0, shares = 0;
  for (size_t i = 0; i < gpu.size(); ++i) {
    for (uint32_t k = 0; k < 4; ++k) shares += ((cpu.words[i] >> (8 * k)) & 0xFFu) != 0xFFu;
    if (gpu[i] != cpu.words[i] && ++differ <= 5) {
      ADD_FAILURE() << c.width << "x" << c.height << " word " << i << " (cell " << i / shader::kClientSoftBandCellWords
                    << "): gpu " << std::hex << gpu[i] << ", cpu " << cpu.words[i];
    }
  }
  std::printf("%ux%u, %u-bit masks, radius %u (cells of %u): %zu words, %zu shares, %zu differ\n", c.width, c.height,
              static_cast<unsigned>(b.mask_bits), c.radius, cpu.cell, gpu.size(), shares, differ);
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(shares, gpu.size() / shader::kClientSoftBandCellWords / 2);  // shares in most cells, not only "none"
}

TEST_F(SoftBandPassTest, CellsOfTwoWithMissingRowsAsTheCpuTable) {
  // dhr-eval's 340x256 buffer: radius 7, cells of 2; one soft and one hard light (8-bit masks).
  expect_same_table(ctx(), {340, 256, {1, 0}, 7, 0, true});
}

TEST_F(SoftBandPassTest, CellsOfFourAndEightWithAFieldLeftOutAsTheCpuTable) {
  // Three soft lights and a hard one (16-bit masks); the second soft light an edge light (its field not refined).
  expect_same_table(ctx(), {1000, 600, {1, 0, 1, 1}, 20, 0b100u, false});
  expect_same_table(ctx(), {1984, 1116, {1, 1, 0, 1}, 40, 0u, true});
}

TEST_F(SoftBandPassTest, MoreSoftFieldsThanRefinedAndTheWidestWindowAsTheCpuTable) {
  // Six soft lights and two hard ones (32-bit masks): the first four soft fields have shares. Radius 100: cells of
  // 16, the window 13 cells across (43,264 pixels a lane can count).
  expect_same_table(ctx(), {600, 420, {1, 1, 0, 1, 1, 1, 0, 1}, kMaxSoftBandRadius, 0, true});
}

// A buffer's upload whose command buffer was abandoned (an error later in the frame, never submitted), then the same
// buffer (same key) uploaded again: the second upload makes the table again instead of trusting the first.
TEST_F(SoftBandPassTest, AnUploadAgainAfterAnAbandonedOneMakesTheTable) {
  const Case c{340, 256, {1, 0}, soft_band_radius(340), 0, false};
  const VisibilityLayout layout = layout_of(c.soft);
  const VisibilityBuffer b = make_buffer(c, layout);
  const uint32_t bits = soft_refine_bits(layout, 0);
  VisibilityInput input;
  input.buffer = &b;
  input.key = 42;
  WarpSourceBuffers buffers(ctx());
  SoftBandPass pass(ctx(), 1);
  shader::ClientWarpSource src{};
  EXPECT_THROW(ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    const SoftBandRequest request{&layout, bits, &pass, 0, cmd};
    buffers.upload(ctx(), Camera{}, input, src, 0, 0, &request);
    throw std::runtime_error("the frame is abandoned");
  }), std::runtime_error);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    const SoftBandRequest request{&layout, bits, &pass, 0, cmd};
    buffers.upload(ctx(), Camera{}, input, src, 0, 0, &request);
  });
  ASSERT_NE(src.flags & shader::kClientSourceHasShares, 0u);
  const SoftBandTable cpu = soft_band_table(layout, b, {}, bits, c.radius);
  std::vector<uint32_t> gpu(cpu.words.size());
  buffers.visibility.read(gpu.data(), gpu.size() * 4, VkDeviceSize{src.share_word} * 4);
  EXPECT_EQ(src.share_columns, cpu.columns);
  EXPECT_TRUE(gpu == cpu.words);
}

TEST_F(SoftBandPassTest, RefusesBadSizesAndAUseOutOfRange) {
  const VisibilityLayout layout = layout_of({1});
  vk::Buffer small(ctx(), 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
  vk::Buffer large(ctx(), 1024, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
  vk::Buffer rows(ctx(), 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
  const std::vector<uint8_t> zeros(1024, 0);
  large.write(zeros.data(), zeros.size());
  rows.write(zeros.data(), 4);
  SoftBandPass pass(ctx(), 1);
  SoftBandSource source;  // 4x4 8-bit masks (16 bytes), the table from byte 16 on: 2x2 cells of 8 words (128 bytes)
  source.visibility = &small;
  source.rows = &rows;
  source.width = 4;
  source.height = 4;
  source.mask_bits = 8;
  source.share_word = 4;
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    EXPECT_THROW(pass.record(cmd, 0, source, layout, 7u, 2), std::invalid_argument);  // the table beyond the buffer
    source.visibility = &large;
    EXPECT_THROW(pass.record(cmd, 1, source, layout, 7u, 2), std::invalid_argument);  // no use 1
    EXPECT_THROW(pass.record(cmd, 0, source, layout, 7u, 0), std::invalid_argument);  // radius 0
    source.share_word = 2;  // the masks would overlap the table
    EXPECT_THROW(pass.record(cmd, 0, source, layout, 7u, 2), std::invalid_argument);
    source.share_word = 4;
    source.mask_bits = 12;
    EXPECT_THROW(pass.record(cmd, 0, source, layout, 7u, 2), std::invalid_argument);
    source.mask_bits = 8;
    source.has_rows = true;
    source.height = 40;  // 40 rows, 32 row bits
    EXPECT_THROW(pass.record(cmd, 0, source, layout, 7u, 2), std::invalid_argument);
    source.height = 4;
    EXPECT_NO_THROW(pass.record(cmd, 0, source, layout, 7u, 2));  // what fits is recorded
  });
  std::vector<uint32_t> table(32);
  large.read(table.data(), table.size() * 4, 16);
  // Every pixel at level 0 (all masks zero): the bottom level keeps its own, so every byte says none.
  EXPECT_TRUE(std::all_of(table.begin(), table.end(), [](uint32_t w) { return w == shader::kClientSoftRefineNoneAll; }));
}

}  // namespace
}  // namespace dhr::render
