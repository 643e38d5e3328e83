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
  bool allow_update = false;      // ALLOW_UPDATE: update_tlas may later move its instances in place
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

// Updates `tlas` in place (VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR) for new instance transforms: the same
// instances, in the same order, over the same BLASes, only transforms (or flags, masks, indices) changed. `tlas` was
// built by build_tlas with these `options` and allow_update set (the flags must match the build's; std::logic_error
// otherwise). Blocks until the update is done; out_stats->build_ms is its host wall time.
void update_tlas(const Context& context, AccelerationStructure& tlas, std::span<const AsInstance> instances,
                 const AsBuildOptions& options, AsBuildStats* out_stats = nullptr);

}  // namespace dhr::vk
