// DHR_VK_CHECK / DHR_VK_TRY and the VkResult names (no device needed).
#include <gtest/gtest.h>

#include <string>

#include "vk/check.hpp"

namespace dhr::vk {
namespace {

VkResult vkFakeCall(VkResult result, int /*unused*/) { return result; }

VkResult try_twice(VkResult first, int* out_calls) {
  ++*out_calls;
  DHR_VK_TRY(vkFakeCall(first, 0));
  ++*out_calls;
  return VK_SUCCESS;
}

TEST(VulkanCheck, ResultNamesCoverCoreAndKhrCodes) {
  EXPECT_STREQ(result_name(VK_SUCCESS), "VK_SUCCESS");
  EXPECT_STREQ(result_name(VK_INCOMPLETE), "VK_INCOMPLETE");
  EXPECT_STREQ(result_name(VK_ERROR_DEVICE_LOST), "VK_ERROR_DEVICE_LOST");
  EXPECT_STREQ(result_name(VK_ERROR_UNKNOWN), "VK_ERROR_UNKNOWN");
  EXPECT_STREQ(result_name(VK_ERROR_OUT_OF_POOL_MEMORY), "VK_ERROR_OUT_OF_POOL_MEMORY");
  EXPECT_STREQ(result_name(VK_ERROR_OUT_OF_DATE_KHR), "VK_ERROR_OUT_OF_DATE_KHR");
  EXPECT_STREQ(result_name(VK_SUBOPTIMAL_KHR), "VK_SUBOPTIMAL_KHR");
  EXPECT_STREQ(result_name(VK_OPERATION_DEFERRED_KHR), "VK_OPERATION_DEFERRED_KHR");
  EXPECT_STREQ(result_name(VK_PIPELINE_COMPILE_REQUIRED), "VK_PIPELINE_COMPILE_REQUIRED");
  EXPECT_STREQ(result_name(static_cast<VkResult>(-123456)), "VK_RESULT_UNKNOWN");
}

TEST(VulkanCheck, CheckThrowsOneLineMessageWithCallAndLocation) {
  int line = 0;
  try {
    line = __LINE__ + 1;
    DHR_VK_CHECK(vkFakeCall(VK_ERROR_DEVICE_LOST, 42));
    FAIL() << "no exception";
  } catch (const VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_DEVICE_LOST);
    const std::string expected =
        "vkFakeCall(...) failed: VK_ERROR_DEVICE_LOST at check_test.cpp:" + std::to_string(line);
    EXPECT_EQ(std::string(e.what()), expected);
  }
}

TEST(VulkanCheck, CheckIgnoresSuccessAndPositiveCodes) {
  EXPECT_NO_THROW(DHR_VK_CHECK(vkFakeCall(VK_SUCCESS, 0)));
  EXPECT_NO_THROW(DHR_VK_CHECK(vkFakeCall(VK_INCOMPLETE, 0)));
}

TEST(VulkanCheck, TryReturnsTheFailure) {
  int calls = 0;
  EXPECT_EQ(try_twice(VK_ERROR_OUT_OF_DEVICE_MEMORY, &calls), VK_ERROR_OUT_OF_DEVICE_MEMORY);
  EXPECT_EQ(calls, 1);
  calls = 0;
  EXPECT_EQ(try_twice(VK_SUCCESS, &calls), VK_SUCCESS);
  EXPECT_EQ(calls, 2);
}

}  // namespace
}  // namespace dhr::vk
