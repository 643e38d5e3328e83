// GPU timestamps: supported on the test device, monotonic, and bounds-checked.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "vk/buffer.hpp"
#include "vk/timestamps.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::vk {
namespace {

using TimestampTest = test::VulkanTest;

TEST_F(TimestampTest, ValuesAreNonDecreasing) {
  TimestampQueries queries(ctx(), 4);
  if (!queries.supported()) {
    if (!test::gpu_requested()) FAIL() << "lavapipe has timestamps: " << queries.unsupported_reason();
    GTEST_SKIP() << queries.unsupported_reason();
  }
  Buffer buffer(ctx(), 1 << 20, VK_BUFFER_USAGE_TRANSFER_DST_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    queries.reset(cmd);
    queries.write(cmd, 0, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT);
    vkCmdFillBuffer(cmd, buffer.handle(), 0, VK_WHOLE_SIZE, 0x12345678u);
    queries.write(cmd, 1);
    vkCmdFillBuffer(cmd, buffer.handle(), 0, VK_WHOLE_SIZE, 0x9abcdef0u);
    queries.write(cmd, 2);
    queries.write(cmd, 3, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT);
  });
  const std::vector<double> ns = queries.read_ns();
  ASSERT_EQ(ns.size(), 4u);
  EXPECT_EQ(ns[0], 0.0);
  for (size_t i = 1; i < ns.size(); ++i) EXPECT_GE(ns[i], ns[i - 1]) << "timestamp " << i;
  const std::vector<uint64_t> ticks = queries.read_ticks();
  ASSERT_EQ(ticks.size(), 4u);
  EXPECT_GT(ticks[0], 0u);
}

TEST_F(TimestampTest, BadIndicesFailClearly) {
  EXPECT_THROW(TimestampQueries(ctx(), 0), std::invalid_argument);
  TimestampQueries queries(ctx(), 2);
  EXPECT_THROW(ctx().submit_and_wait([&](VkCommandBuffer cmd) { queries.write(cmd, 2); }), std::out_of_range);
}

TEST(TimestampUnsupported, DefaultConstructedReportsNothing) {
  const TimestampQueries queries;
  EXPECT_FALSE(queries.supported());
  EXPECT_TRUE(queries.read_ns().empty());
}

}  // namespace
}  // namespace dhr::vk
