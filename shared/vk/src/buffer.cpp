#include "vk/buffer.hpp"

#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "vk/barriers.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"

namespace dhr::vk {

Buffer::Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage,
               VkMemoryPropertyFlags memory_flags)
    : device_(context.device()), size_(size), usage_(usage) {
  if (size == 0) throw std::invalid_argument("Vulkan buffer size must be > 0");
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  DHR_VK_CHECK(vkCreateBuffer(device_, &info, nullptr, &buffer_));
  try {
    VkMemoryRequirements requirements{};
    vkGetBufferMemoryRequirements(device_, buffer_, &requirements);
    const bool want_host = (memory_flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0;
    uint32_t type = 0;
    if (want_host) {
      // Coherent memory spares flush/invalidate calls; fall back to non-coherent if that is all there is.
      try {
        type = context.find_memory_type(requirements.memoryTypeBits,
                                        memory_flags | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
      } catch (const std::runtime_error&) {
        type = context.find_memory_type(requirements.memoryTypeBits, memory_flags);
      }
    } else {
      type = context.find_memory_type(requirements.memoryTypeBits, memory_flags);
    }
    memory_flags_ = context.memory_properties().memoryTypes[type].propertyFlags;

    VkMemoryAllocateFlagsInfo flags{};
    flags.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO;
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    alloc.pNext = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0 ? &flags : nullptr;
    alloc.allocationSize = requirements.size;
    alloc.memoryTypeIndex = type;
    DHR_VK_CHECK(vkAllocateMemory(device_, &alloc, nullptr, &memory_));
    DHR_VK_CHECK(vkBindBufferMemory(device_, buffer_, memory_, 0));
    // Mapped only when asked for, so the transfer path is the same on every device (on lavapipe
    // all memory is host-visible; tests still exercise the staging path).
    if (want_host) DHR_VK_CHECK(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
    if (alloc.pNext != nullptr) {
      VkBufferDeviceAddressInfo address{};
      address.sType = VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO;
      address.buffer = buffer_;
      address_ = vkGetBufferDeviceAddress(device_, &address);
    }
  } catch (...) {
    destroy();
    throw;
  }
}

Buffer::~Buffer() { destroy(); }

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    destroy();
    device_ = other.device_;
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(other.size_, 0);
    usage_ = std::exchange(other.usage_, 0);
    memory_flags_ = std::exchange(other.memory_flags_, 0);
    address_ = std::exchange(other.address_, 0);
    mapped_ = std::exchange(other.mapped_, nullptr);
  }
  return *this;
}

void Buffer::destroy() {
  if (buffer_ != VK_NULL_HANDLE) vkDestroyBuffer(device_, buffer_, nullptr);
  if (memory_ != VK_NULL_HANDLE) vkFreeMemory(device_, memory_, nullptr);  // also unmaps
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
}

void Buffer::check_range(VkDeviceSize size, VkDeviceSize offset) const {
  if (offset > size_ || size > size_ - offset) {
    throw std::out_of_range("Vulkan buffer access of " + std::to_string(size) + " bytes at offset " +
                            std::to_string(offset) + " exceeds its size " + std::to_string(size_));
  }
}

void Buffer::write(const void* data, VkDeviceSize size, VkDeviceSize offset) {
  if (mapped_ == nullptr) throw std::logic_error("Buffer::write on a buffer that is not host-visible");
  check_range(size, offset);
  if (size == 0) return;
  std::memcpy(static_cast<std::byte*>(mapped_) + offset, data, size);
  if ((memory_flags_ & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) == 0) {
    const VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0, VK_WHOLE_SIZE};
    DHR_VK_CHECK(vkFlushMappedMemoryRanges(device_, 1, &range));
  }
}

void Buffer::read(void* out_data, VkDeviceSize size, VkDeviceSize offset) const {
  if (mapped_ == nullptr) throw std::logic_error("Buffer::read on a buffer that is not host-visible");
  check_range(size, offset);
  if (size == 0) return;
  if ((memory_flags_ & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) == 0) {
    const VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0, VK_WHOLE_SIZE};
    DHR_VK_CHECK(vkInvalidateMappedMemoryRanges(device_, 1, &range));
  }
  std::memcpy(out_data, static_cast<const std::byte*>(mapped_) + offset, size);
}

void upload_to_buffer(const Context& context, Buffer& dst, const void* data, VkDeviceSize size,
                      VkDeviceSize dst_offset) {
  if (dst.host_visible()) {
    dst.write(data, size, dst_offset);
    return;
  }
  if (dst_offset > dst.size() || size > dst.size() - dst_offset) {
    throw std::out_of_range("upload_to_buffer: " + std::to_string(size) + " bytes at offset " +
                            std::to_string(dst_offset) + " exceed the buffer size " + std::to_string(dst.size()));
  }
  if (size == 0) return;
  if ((dst.usage() & VK_BUFFER_USAGE_TRANSFER_DST_BIT) == 0) {
    throw std::logic_error("upload_to_buffer: device-local buffer lacks VK_BUFFER_USAGE_TRANSFER_DST_BIT");
  }
  Buffer staging(context, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  staging.write(data, size);
  context.submit_and_wait([&](VkCommandBuffer cmd) {
    // Earlier work may still read or write the destination range.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkBufferCopy region{0, dst_offset, size};
    vkCmdCopyBuffer(cmd, staging.handle(), dst.handle(), 1, &region);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  });
}

void read_buffer(const Context& context, const Buffer& src, void* out_data, VkDeviceSize size,
                 VkDeviceSize src_offset) {
  if (src.host_visible()) {
    // Device writes of earlier submissions must be made visible to the host first.
    context.submit_and_wait([](VkCommandBuffer cmd) {
      memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    });
    src.read(out_data, size, src_offset);
    return;
  }
  if (src_offset > src.size() || size > src.size() - src_offset) {
    throw std::out_of_range("read_buffer: " + std::to_string(size) + " bytes at offset " + std::to_string(src_offset) +
                            " exceed the buffer size " + std::to_string(src.size()));
  }
  if (size == 0) return;
  if ((src.usage() & VK_BUFFER_USAGE_TRANSFER_SRC_BIT) == 0) {
    throw std::logic_error("read_buffer: device-local buffer lacks VK_BUFFER_USAGE_TRANSFER_SRC_BIT");
  }
  Buffer staging(context, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  context.submit_and_wait([&](VkCommandBuffer cmd) {
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    const VkBufferCopy region{src_offset, 0, size};
    vkCmdCopyBuffer(cmd, src.handle(), staging.handle(), 1, &region);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  });
  staging.read(out_data, size);
}

Buffer create_buffer_with_data(const Context& context, std::span<const std::byte> data, VkBufferUsageFlags usage,
                               VkMemoryPropertyFlags memory_flags) {
  Buffer buffer(context, data.size_bytes(), usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, memory_flags);
  upload_to_buffer(context, buffer, data.data(), data.size_bytes());
  return buffer;
}

}  // namespace dhr::vk
