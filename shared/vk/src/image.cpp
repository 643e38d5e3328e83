#include "vk/image.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "vk/barriers.hpp"
#include "vk/buffer.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"

namespace dhr::vk {
namespace {

struct StageAccess {
  VkPipelineStageFlags2 stage;
  VkAccessFlags2 access;
};

// Where and how an image in `layout` is used. Broad on purpose (ALL_COMMANDS for shader access):
// stage bits like RAY_TRACING_SHADER are invalid on devices without that feature.
StageAccess layout_usage(VkImageLayout layout) {
  switch (layout) {
    case VK_IMAGE_LAYOUT_UNDEFINED:
    case VK_IMAGE_LAYOUT_PREINITIALIZED:
      return {VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE};
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL:
      return {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT};
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL:
      return {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT};
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL:
    case VK_IMAGE_LAYOUT_READ_ONLY_OPTIMAL:
    case VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL:
    case VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL:
      return {VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_INPUT_ATTACHMENT_READ_BIT};
    case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL:
      return {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
              VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT};
    case VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL:
    case VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL:
      return {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
              VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT};
    default:  // GENERAL, ATTACHMENT_OPTIMAL, PRESENT_SRC and anything else: everything
      return {VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT};
  }
}

void check_pixel_bytes(const Image& image, size_t byte_count, const char* what) {
  const size_t expected = size_t{image.width()} * image.height() * format_texel_size(image.format());
  if (byte_count != expected) {
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(byte_count) + " bytes given, a " +
                                std::to_string(image.width()) + "x" + std::to_string(image.height()) +
                                " image holds " + std::to_string(expected));
  }
}

VkBufferImageCopy whole_image_copy(const Image& image) {
  VkBufferImageCopy region{};
  // Copies address one aspect; for depth images that is the depth.
  const VkImageAspectFlags aspect =
      (image.aspect() & VK_IMAGE_ASPECT_DEPTH_BIT) != 0 ? VkImageAspectFlags{VK_IMAGE_ASPECT_DEPTH_BIT} : image.aspect();
  region.imageSubresource = {aspect, 0, 0, 1};
  region.imageExtent = {image.width(), image.height(), 1};
  return region;
}

}  // namespace

uint32_t format_texel_size(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R8_UNORM: case VK_FORMAT_R8_UINT: case VK_FORMAT_R8_SNORM: case VK_FORMAT_R8_SINT:
    case VK_FORMAT_S8_UINT:
      return 1;
    case VK_FORMAT_R8G8_UNORM: case VK_FORMAT_R8G8_UINT: case VK_FORMAT_R16_SFLOAT: case VK_FORMAT_R16_UINT:
    case VK_FORMAT_R16_UNORM: case VK_FORMAT_D16_UNORM:
      return 2;
    case VK_FORMAT_R8G8B8A8_UNORM: case VK_FORMAT_R8G8B8A8_SRGB: case VK_FORMAT_R8G8B8A8_UINT:
    case VK_FORMAT_R8G8B8A8_SNORM: case VK_FORMAT_B8G8R8A8_UNORM: case VK_FORMAT_B8G8R8A8_SRGB:
    case VK_FORMAT_R16G16_SFLOAT: case VK_FORMAT_R16G16_UINT: case VK_FORMAT_R16G16_UNORM:
    case VK_FORMAT_R16G16_SNORM: case VK_FORMAT_R32_SFLOAT: case VK_FORMAT_R32_UINT: case VK_FORMAT_R32_SINT:
    case VK_FORMAT_A2B10G10R10_UNORM_PACK32: case VK_FORMAT_A2R10G10B10_UNORM_PACK32:
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32: case VK_FORMAT_D32_SFLOAT: case VK_FORMAT_X8_D24_UNORM_PACK32:
      return 4;
    case VK_FORMAT_R16G16B16A16_SFLOAT: case VK_FORMAT_R16G16B16A16_UINT: case VK_FORMAT_R16G16B16A16_UNORM:
    case VK_FORMAT_R32G32_SFLOAT: case VK_FORMAT_R32G32_UINT: case VK_FORMAT_R32G32_SINT:
      return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT: case VK_FORMAT_R32G32B32A32_UINT: case VK_FORMAT_R32G32B32A32_SINT:
      return 16;
    default:
      throw std::invalid_argument("format_texel_size: VkFormat " + std::to_string(static_cast<int>(format)) +
                                  " is not a supported uncompressed single-aspect format");
  }
}

VkImageAspectFlags format_aspect(VkFormat format) {
  switch (format) {
    case VK_FORMAT_D16_UNORM: case VK_FORMAT_D32_SFLOAT: case VK_FORMAT_X8_D24_UNORM_PACK32:
      return VK_IMAGE_ASPECT_DEPTH_BIT;
    case VK_FORMAT_D16_UNORM_S8_UINT: case VK_FORMAT_D24_UNORM_S8_UINT: case VK_FORMAT_D32_SFLOAT_S8_UINT:
      return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
    case VK_FORMAT_S8_UINT:
      return VK_IMAGE_ASPECT_STENCIL_BIT;
    default:
      return VK_IMAGE_ASPECT_COLOR_BIT;
  }
}

Image::Image(const Context& context, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage)
    : device_(context.device()), format_(format), usage_(usage), aspect_(format_aspect(format)), width_(width),
      height_(height) {
  if (width == 0 || height == 0) throw std::invalid_argument("Vulkan image size must be at least 1x1");
  VkImageCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width, height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  DHR_VK_CHECK(vkCreateImage(device_, &info, nullptr, &image_));
  try {
    VkMemoryRequirements requirements{};
    vkGetImageMemoryRequirements(device_, image_, &requirements);
    VkMemoryAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    alloc.allocationSize = requirements.size;
    alloc.memoryTypeIndex =
        context.find_memory_type(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    DHR_VK_CHECK(vkAllocateMemory(device_, &alloc, nullptr, &memory_));
    DHR_VK_CHECK(vkBindImageMemory(device_, image_, memory_, 0));
    constexpr VkImageUsageFlags kViewUsages =
        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
        VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_INPUT_ATTACHMENT_BIT;
    if ((usage & kViewUsages) != 0) {
      VkImageViewCreateInfo view{};
      view.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
      view.image = image_;
      view.viewType = VK_IMAGE_VIEW_TYPE_2D;
      view.format = format;
      // A combined depth/stencil view for sampling must name one aspect: depth.
      const VkImageAspectFlags view_aspect =
          (aspect_ & VK_IMAGE_ASPECT_DEPTH_BIT) != 0 ? VkImageAspectFlags{VK_IMAGE_ASPECT_DEPTH_BIT} : aspect_;
      view.subresourceRange = {view_aspect, 0, 1, 0, 1};
      DHR_VK_CHECK(vkCreateImageView(device_, &view, nullptr, &view_));
    }
  } catch (...) {
    destroy();
    throw;
  }
}

Image::~Image() { destroy(); }

Image::Image(Image&& other) noexcept { *this = std::move(other); }

Image& Image::operator=(Image&& other) noexcept {
  if (this != &other) {
    destroy();
    device_ = other.device_;
    image_ = std::exchange(other.image_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    view_ = std::exchange(other.view_, VK_NULL_HANDLE);
    format_ = other.format_;
    usage_ = other.usage_;
    aspect_ = other.aspect_;
    width_ = std::exchange(other.width_, 0);
    height_ = std::exchange(other.height_, 0);
    layout_ = std::exchange(other.layout_, VK_IMAGE_LAYOUT_UNDEFINED);
  }
  return *this;
}

void Image::destroy() {
  if (view_ != VK_NULL_HANDLE) vkDestroyImageView(device_, view_, nullptr);
  if (image_ != VK_NULL_HANDLE) vkDestroyImage(device_, image_, nullptr);
  if (memory_ != VK_NULL_HANDLE) vkFreeMemory(device_, memory_, nullptr);
  view_ = VK_NULL_HANDLE;
  image_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

void Image::transition(VkCommandBuffer cmd, VkImageLayout new_layout) {
  transition_image_layout(cmd, image_, aspect_, layout_, new_layout);
  layout_ = new_layout;
}

void transition_image_layout(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout old_layout,
                             VkImageLayout new_layout) {
  const StageAccess src = layout_usage(old_layout);
  const StageAccess dst = layout_usage(new_layout);
  // Writes only need to be made available; reads in the source scope need only an execution dependency.
  constexpr VkAccessFlags2 kWrites = VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                                     VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT |
                                     VK_ACCESS_2_SHADER_WRITE_BIT;
  image_barrier(cmd, image, aspect, old_layout, new_layout, src.stage, src.access & kWrites, dst.stage, dst.access);
}

void upload_image(const Context& context, Image& image, const void* pixels, size_t byte_count,
                  VkImageLayout final_layout) {
  check_pixel_bytes(image, byte_count, "upload_image");
  if ((image.usage() & VK_IMAGE_USAGE_TRANSFER_DST_BIT) == 0) {
    throw std::logic_error("upload_image: image lacks VK_IMAGE_USAGE_TRANSFER_DST_BIT");
  }
  Buffer staging(context, byte_count, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  staging.write(pixels, byte_count);
  const VkImageLayout before = image.layout();
  try {
    context.submit_and_wait([&](VkCommandBuffer cmd) {
      image.transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
      const VkBufferImageCopy region = whole_image_copy(image);
      vkCmdCopyBufferToImage(cmd, staging.handle(), image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
      image.transition(cmd, final_layout);
    });
  } catch (...) {
    image.set_layout(before);
    throw;
  }
}

void read_image(const Context& context, Image& image, void* out_pixels, size_t byte_count) {
  check_pixel_bytes(image, byte_count, "read_image");
  if ((image.usage() & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) == 0) {
    throw std::logic_error("read_image: image lacks VK_IMAGE_USAGE_TRANSFER_SRC_BIT");
  }
  Buffer staging(context, byte_count, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  const VkImageLayout before = image.layout();
  const VkImageLayout after = before == VK_IMAGE_LAYOUT_UNDEFINED ? VK_IMAGE_LAYOUT_GENERAL : before;
  try {
    context.submit_and_wait([&](VkCommandBuffer cmd) {
      // Writes of earlier submissions (any stage) must be visible to the copy.
      memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
      image.transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
      const VkBufferImageCopy region = whole_image_copy(image);
      vkCmdCopyImageToBuffer(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.handle(), 1, &region);
      memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
      image.transition(cmd, after);
    });
  } catch (...) {
    image.set_layout(before);
    throw;
  }
  staging.read(out_pixels, byte_count);
}

}  // namespace dhr::vk
