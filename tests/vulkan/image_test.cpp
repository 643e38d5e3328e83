// Image creation, layout tracking, upload/readback of tightly packed pixels.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "vk/image.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::vk {
namespace {

using ImageTest = test::VulkanTest;

constexpr VkImageUsageFlags kTransfer = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;

TEST_F(ImageTest, Rgba8RoundTripWithOddSize) {
  constexpr uint32_t kWidth = 37;
  constexpr uint32_t kHeight = 23;
  std::mt19937 rng(42);
  std::vector<uint8_t> pixels(kWidth * kHeight * 4);
  for (uint8_t& p : pixels) p = static_cast<uint8_t>(rng());
  Image image(ctx(), kWidth, kHeight, VK_FORMAT_R8G8B8A8_UNORM, kTransfer | VK_IMAGE_USAGE_SAMPLED_BIT);
  EXPECT_NE(image.view(), VK_NULL_HANDLE);
  EXPECT_EQ(image.layout(), VK_IMAGE_LAYOUT_UNDEFINED);
  upload_image(ctx(), image, pixels.data(), pixels.size());
  EXPECT_EQ(image.layout(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  std::vector<uint8_t> back(pixels.size(), 0);
  read_image(ctx(), image, back.data(), back.size());
  EXPECT_EQ(back, pixels);
  EXPECT_EQ(image.layout(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);  // restored after the readback
}

TEST_F(ImageTest, FloatImageRoundTripIntoGeneralLayout) {
  constexpr uint32_t kWidth = 16;
  constexpr uint32_t kHeight = 9;
  std::vector<float> texels(kWidth * kHeight);
  for (size_t i = 0; i < texels.size(); ++i) texels[i] = static_cast<float>(i) * 0.25f - 3.0f;
  Image image(ctx(), kWidth, kHeight, VK_FORMAT_R32_SFLOAT, kTransfer | VK_IMAGE_USAGE_STORAGE_BIT);
  upload_image(ctx(), image, texels.data(), texels.size() * sizeof(float), VK_IMAGE_LAYOUT_GENERAL);
  EXPECT_EQ(image.layout(), VK_IMAGE_LAYOUT_GENERAL);
  std::vector<float> back(texels.size(), 0.0f);
  read_image(ctx(), image, back.data(), back.size() * sizeof(float));
  EXPECT_EQ(back, texels);
}

TEST_F(ImageTest, RecordedTransitionsAndClearAreReadBack) {
  Image image(ctx(), 8, 4, VK_FORMAT_R32_UINT, kTransfer);
  EXPECT_EQ(image.view(), VK_NULL_HANDLE);  // transfer-only usage allows no view
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    image.transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkClearColorValue color{};
    color.uint32[0] = 0xC0FFEEu;
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &color, 1, &range);
    image.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
  });
  std::vector<uint32_t> back(8 * 4, 0);
  read_image(ctx(), image, back.data(), back.size() * 4);
  for (uint32_t v : back) EXPECT_EQ(v, 0xC0FFEEu);
}

TEST_F(ImageTest, BadRequestsFailClearly) {
  EXPECT_THROW(Image(ctx(), 0, 4, VK_FORMAT_R8G8B8A8_UNORM, kTransfer), std::invalid_argument);
  Image image(ctx(), 4, 4, VK_FORMAT_R8G8B8A8_UNORM, kTransfer);
  std::vector<uint8_t> wrong(4 * 4 * 4 - 1);
  EXPECT_THROW(upload_image(ctx(), image, wrong.data(), wrong.size()), std::invalid_argument);
  EXPECT_THROW(read_image(ctx(), image, wrong.data(), wrong.size()), std::invalid_argument);
  Image sampled_only(ctx(), 4, 4, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT);
  std::vector<uint8_t> right(4 * 4 * 4);
  EXPECT_THROW(upload_image(ctx(), sampled_only, right.data(), right.size()), std::logic_error);
  EXPECT_THROW(format_texel_size(VK_FORMAT_BC1_RGB_UNORM_BLOCK), std::invalid_argument);
  EXPECT_EQ(format_texel_size(VK_FORMAT_R16G16B16A16_SFLOAT), 8u);
  EXPECT_EQ(format_aspect(VK_FORMAT_D32_SFLOAT), VkImageAspectFlags{VK_IMAGE_ASPECT_DEPTH_BIT});
}

}  // namespace
}  // namespace dhr::vk
