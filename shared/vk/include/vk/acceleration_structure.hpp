// Ray-tracing acceleration structures: bottom level from triangles, top level from instances,
// optionally compacted. Needs a Context created with ray tracing enabled.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>

#include "vk/buffer.hpp"

namespace dhr::vk {

class Context;

// Owns the acceleration structure handle and its storage buffer (move-only).
class AccelerationStructure {
 public:
  AccelerationStructure() = default;
  // Creates an (unbuilt) structure of `size` bytes.
  AccelerationStructure(const Context& context, VkAccelerationStructureTypeKHR type, VkDeviceSize size);
  ~AccelerationStructure();
  AccelerationStructure(AccelerationStructure&& other) noexcept;
  AccelerationStructure& operator=(AccelerationStructure&& other) noexcept;
  AccelerationStructure(const AccelerationStructure&) = delete;
  AccelerationStructure& operator=(const AccelerationStructure&) = delete;

  VkAccelerationStructureKHR handle() const { return handle_; }
  VkDeviceAddress address() const { return address_; }
  const Buffer& buffer() const { return buffer_; }
  VkDeviceSize size() const { return buffer_.size(); }
  explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }

 private:
  void destroy();

  VkDevice device_ = VK_NULL_HANDLE;
  PFN_vkDestroyAccelerationStructureKHR destroy_fn_ = nullptr;
  VkAccelerationStructureKHR handle_ = VK_NULL_HANDLE;
  VkDeviceAddress address_ = 0;
  Buffer buffer_;
};

struct AsBuildOptions {
  bool compact = true;            // copy into a right-sized structure after the build
  bool prefer_fast_trace = true;  // else PREFER_FAST_BUILD
};

struct AsBuildStats {
  double build_ms = 0.0;        // host wall time of the build submission
  double compact_ms = 0.0;      // host wall time of the compacting copy (0 without compaction)
  VkDeviceSize build_size = 0;  // structure size before compaction
  VkDeviceSize final_size = 0;  // size of the returned structure
  VkDeviceSize scratch_size = 0;
  uint32_t primitive_count = 0;  // triangles (BLAS) or instances (TLAS)
};

// One opaque triangle geometry read from device memory: float3 positions, uint32 indices.
// The buffers need ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR and
// SHADER_DEVICE_ADDRESS_BIT usage; the caller guarantees every index < vertex_count.
struct TriangleGeometry {
  VkDeviceAddress vertex_address = 0;
  uint32_t vertex_count = 0;
  VkDeviceSize vertex_stride = 3 * sizeof(float);
  VkDeviceAddress index_address = 0;
  uint32_t triangle_count = 0;
};

AccelerationStructure build_blas(const Context& context, std::span<const TriangleGeometry> geometries,
                                 const AsBuildOptions& options = {}, AsBuildStats* out_stats = nullptr);

// Convenience: validates (indices in range, whole triangles), uploads and builds one geometry.
// positions_xyz holds x, y, z per vertex.
AccelerationStructure build_blas(const Context& context, std::span<const float> positions_xyz,
                                 std::span<const uint32_t> indices, const AsBuildOptions& options = {},
                                 AsBuildStats* out_stats = nullptr);

struct AsInstance {
  const AccelerationStructure* blas = nullptr;
  // Row-major 3x4 object-to-world transform (rotation/scale in the 3x3 part, translation in column 3).
  float transform[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
  uint32_t custom_index = 0;  // 24 bits, gl_InstanceCustomIndexEXT
  uint8_t mask = 0xFF;        // tested against the ray's cull mask
  uint32_t sbt_offset = 0;    // 24 bits, hit group offset
  VkGeometryInstanceFlagsKHR flags = 0;
};

AccelerationStructure build_tlas(const Context& context, std::span<const AsInstance> instances,
                                 const AsBuildOptions& options = {}, AsBuildStats* out_stats = nullptr);

}  // namespace dhr::vk
