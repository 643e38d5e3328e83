// 2D image with its own memory and view (move-only), layout transitions, pixel upload/readback.
#pragma once
#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>

namespace dhr::vk {

class Context;

class Image {
 public:
  Image() = default;
  // One mip level, one layer, optimal tiling, device-local. A view is created when the usage
  // allows one (sampled, storage, attachment); view() is VK_NULL_HANDLE otherwise.
  Image(const Context& context, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage);
  ~Image();
  Image(Image&& other) noexcept;
  Image& operator=(Image&& other) noexcept;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }
  VkFormat format() const { return format_; }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  VkExtent2D extent() const { return {width_, height_}; }
  VkImageUsageFlags usage() const { return usage_; }
  VkImageAspectFlags aspect() const { return aspect_; }
  explicit operator bool() const { return image_ != VK_NULL_HANDLE; }

  // Layout as last recorded through transition()/set_layout() (host-side tracking: record in
  // submission order). Starts as VK_IMAGE_LAYOUT_UNDEFINED.
  VkImageLayout layout() const { return layout_; }
  // Records a barrier from layout() to new_layout (stages/accesses derived from both layouts).
  void transition(VkCommandBuffer cmd, VkImageLayout new_layout);
  // Records that something else (a render pass, the XR compositor) changed the layout.
  void set_layout(VkImageLayout layout) { layout_ = layout; }

 private:
  void destroy();

  VkDevice device_ = VK_NULL_HANDLE;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkImageUsageFlags usage_ = 0;
  VkImageAspectFlags aspect_ = 0;
  uint32_t width_ = 0;
  uint32_t height_ = 0;
  VkImageLayout layout_ = VK_IMAGE_LAYOUT_UNDEFINED;
};

// Barrier for a layout change with conservative stages/accesses derived from the two layouts.
void transition_image_layout(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout old_layout,
                             VkImageLayout new_layout);

// Bytes per texel of common uncompressed formats; throws std::invalid_argument for others
// (including combined depth/stencil, whose copies are per aspect).
uint32_t format_texel_size(VkFormat format);
// DEPTH for depth formats, DEPTH|STENCIL for combined, STENCIL for S8, COLOR otherwise.
VkImageAspectFlags format_aspect(VkFormat format);

// Uploads tightly packed rows (byte_count == width * height * texel size) through a staging buffer
// (image needs TRANSFER_DST usage) and leaves the image in final_layout. Blocks until done.
void upload_image(const Context& context, Image& image, const void* pixels, size_t byte_count,
                  VkImageLayout final_layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);

// Reads the image back as tightly packed rows (image needs TRANSFER_SRC usage) after all previously
// submitted work; the image returns to its layout (GENERAL if it was UNDEFINED). Blocks until done.
void read_image(const Context& context, Image& image, void* out_pixels, size_t byte_count);

}  // namespace dhr::vk
