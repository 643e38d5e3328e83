// Buffer ownership, mapping, device addresses and host <-> device transfers.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "vk/buffer.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::vk {
namespace {

using BufferTest = test::VulkanTest;

std::vector<uint32_t> pattern(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint32_t> values(count);
  for (uint32_t& v : values) v = static_cast<uint32_t>(rng());
  return values;
}

constexpr VkBufferUsageFlags kTransfer = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

TEST_F(BufferTest, DeviceLocalRoundTripGoesThroughStaging) {
  const std::vector<uint32_t> data = pattern(64 * 1024, 7);
  const VkDeviceSize bytes = data.size() * sizeof(uint32_t);
  Buffer buffer(ctx(), bytes, kTransfer | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  EXPECT_FALSE(buffer.host_visible());  // not mapped: the transfer path is the staging one
  EXPECT_EQ(buffer.size(), bytes);
  EXPECT_TRUE(buffer.memory_flags() & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  upload_to_buffer(ctx(), buffer, data.data(), bytes);
  std::vector<uint32_t> back(data.size(), 0);
  read_buffer(ctx(), buffer, back.data(), bytes);
  EXPECT_EQ(back, data);

  // Partial update at an offset, then a partial read of the same range.
  const std::vector<uint32_t> patch = pattern(100, 8);
  upload_to_buffer(ctx(), buffer, patch.data(), patch.size() * 4, 1000 * 4);
  std::vector<uint32_t> window(patch.size(), 0);
  read_buffer(ctx(), buffer, window.data(), window.size() * 4, 1000 * 4);
  EXPECT_EQ(window, patch);
  uint32_t before_patch = 0;
  read_buffer(ctx(), buffer, &before_patch, 4, 999 * 4);
  EXPECT_EQ(before_patch, data[999]);
}

TEST_F(BufferTest, DeviceCopyBetweenBuffersIsVisibleOnReadback) {
  const std::vector<uint32_t> data = pattern(4096, 11);
  const VkDeviceSize bytes = data.size() * 4;
  Buffer src = create_buffer_with_data(ctx(), std::span<const uint32_t>(data), kTransfer);
  Buffer dst(ctx(), bytes, kTransfer, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    const VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(cmd, src.handle(), dst.handle(), 1, &region);
  });
  std::vector<uint32_t> back(data.size(), 0);
  read_buffer(ctx(), dst, back.data(), bytes);
  EXPECT_EQ(back, data);
}

TEST_F(BufferTest, HostVisibleBufferIsMapped) {
  Buffer buffer(ctx(), 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  ASSERT_TRUE(buffer.host_visible());
  ASSERT_NE(buffer.mapped(), nullptr);
  const std::vector<uint32_t> data = pattern(64, 3);
  upload_to_buffer(ctx(), buffer, data.data(), 256);
  std::vector<uint32_t> back(64, 0);
  read_buffer(ctx(), buffer, back.data(), 256);
  EXPECT_EQ(back, data);
}

TEST_F(BufferTest, DeviceAddressOnlyWhenRequested) {
  const Buffer with(ctx(), 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                    VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  const Buffer without(ctx(), 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  EXPECT_NE(with.address(), 0u);
  EXPECT_EQ(without.address(), 0u);
}

TEST_F(BufferTest, MoveTransfersOwnership) {
  Buffer a(ctx(), 128, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  const VkBuffer handle = a.handle();
  Buffer b(std::move(a));
  EXPECT_FALSE(a);  // NOLINT(bugprone-use-after-move): checking the moved-from state
  EXPECT_EQ(b.handle(), handle);
  Buffer c(ctx(), 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  c = std::move(b);  // destroys c's old buffer
  EXPECT_EQ(c.handle(), handle);
  EXPECT_EQ(c.size(), 128u);
}

TEST_F(BufferTest, BadRequestsFailClearly) {
  EXPECT_THROW(Buffer(ctx(), 0, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 0), std::invalid_argument);
  Buffer device_only(ctx(), 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  uint32_t value = 1;
  EXPECT_THROW(upload_to_buffer(ctx(), device_only, &value, 4), std::logic_error);  // no TRANSFER_DST
  EXPECT_THROW(read_buffer(ctx(), device_only, &value, 4), std::logic_error);       // no TRANSFER_SRC
  EXPECT_THROW(device_only.write(&value, 4), std::logic_error);                     // not mapped
  Buffer small(ctx(), 16, kTransfer, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  EXPECT_THROW(upload_to_buffer(ctx(), small, &value, 4, 16), std::out_of_range);
  EXPECT_THROW(read_buffer(ctx(), small, &value, 4, 13), std::out_of_range);
  Buffer mapped(ctx(), 16, 0 | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  EXPECT_THROW(mapped.write(&value, 4, ~VkDeviceSize{0}), std::out_of_range);
}

}  // namespace
}  // namespace dhr::vk
