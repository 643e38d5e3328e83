// Buffer with its own dedicated memory (move-only), plus host <-> buffer transfer helpers.
#pragma once
#include <vulkan/vulkan.h>

#include <cstddef>
#include <span>

namespace dhr::vk {

class Context;

class Buffer {
 public:
  Buffer() = default;
  // size > 0. Requested memory_flags containing HOST_VISIBLE: mapped for the buffer's lifetime
  // (HOST_COHERENT preferred). Usage with SHADER_DEVICE_ADDRESS: address() is filled.
  Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags memory_flags);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  VkBufferUsageFlags usage() const { return usage_; }
  VkMemoryPropertyFlags memory_flags() const { return memory_flags_; }  // of the chosen memory type
  VkDeviceAddress address() const { return address_; }                  // 0 without SHADER_DEVICE_ADDRESS
  void* mapped() const { return mapped_; }                              // nullptr unless host-visible
  bool host_visible() const { return mapped_ != nullptr; }
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

  // Host-visible buffers only: copy bytes in/out (flushing/invalidating non-coherent memory).
  // Throw std::logic_error when not mapped, std::out_of_range when the range exceeds the buffer.
  void write(const void* data, VkDeviceSize size, VkDeviceSize offset = 0);
  void read(void* out_data, VkDeviceSize size, VkDeviceSize offset = 0) const;

 private:
  void destroy();
  void check_range(VkDeviceSize size, VkDeviceSize offset) const;

  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  VkBufferUsageFlags usage_ = 0;
  VkMemoryPropertyFlags memory_flags_ = 0;
  VkDeviceAddress address_ = 0;
  void* mapped_ = nullptr;
};

// Copies host bytes into dst. Host-visible buffers are written directly; others go through a
// staging buffer and a transfer (dst needs TRANSFER_DST usage). Blocks until done; afterwards the
// data is visible to any later command on the context's queue.
void upload_to_buffer(const Context& context, Buffer& dst, const void* data, VkDeviceSize size,
                      VkDeviceSize dst_offset = 0);

// Copies bytes out of src after all previously submitted work; non-host-visible buffers go
// through a staging buffer (src needs TRANSFER_SRC usage). Blocks until done.
void read_buffer(const Context& context, const Buffer& src, void* out_data, VkDeviceSize size,
                 VkDeviceSize src_offset = 0);

// Creates a buffer of data.size_bytes() (TRANSFER_DST is added to usage) and uploads data.
Buffer create_buffer_with_data(const Context& context, std::span<const std::byte> data, VkBufferUsageFlags usage,
                               VkMemoryPropertyFlags memory_flags = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);

template <typename T>
Buffer create_buffer_with_data(const Context& context, std::span<const T> data, VkBufferUsageFlags usage,
                               VkMemoryPropertyFlags memory_flags = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) {
  return create_buffer_with_data(context, std::as_bytes(data), usage, memory_flags);
}

}  // namespace dhr::vk
