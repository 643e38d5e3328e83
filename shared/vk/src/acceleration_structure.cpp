#include "vk/acceleration_structure.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "vk/barriers.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"
#include "vk/handle.hpp"

namespace dhr::vk {
namespace {

constexpr uint32_t kMax24Bit = (1u << 24) - 1;

void require_ray_tracing(const Context& context) {
  if (!context.info().ray_tracing.enabled()) {
    throw std::logic_error("acceleration structures need a Context with ray tracing enabled "
                           "(ContextOptions::want_ray_tracing on a device that supports it)");
  }
}

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

// The build, the compacted-size query and the copy all touch the structure: make each step's
// writes visible to everything that follows (later builds, queries, copies, traces).
void after_build_barrier(VkCommandBuffer cmd) {
  memory_barrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                 VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                 VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR | VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR |
                     VK_ACCESS_2_SHADER_READ_BIT);
}

AccelerationStructure build(const Context& context, VkAccelerationStructureTypeKHR type,
                            const std::vector<VkAccelerationStructureGeometryKHR>& geometries,
                            const std::vector<uint32_t>& primitive_counts, const AsBuildOptions& options,
                            AsBuildStats* out_stats) {
  const RayTracingDispatch& rt = context.rt();
  const VkDevice device = context.device();
  VkAccelerationStructureBuildGeometryInfoKHR build_info{};
  build_info.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR;
  build_info.type = type;
  build_info.flags = options.prefer_fast_trace ? VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR
                                               : VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_BUILD_BIT_KHR;
  if (options.compact) build_info.flags |= VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_COMPACTION_BIT_KHR;
  if (options.allow_update) build_info.flags |= VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_UPDATE_BIT_KHR;
  build_info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  build_info.geometryCount = static_cast<uint32_t>(geometries.size());
  build_info.pGeometries = geometries.data();

  VkAccelerationStructureBuildSizesInfoKHR sizes{};
  sizes.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR;
  rt.get_acceleration_structure_build_sizes(device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &build_info,
                                            primitive_counts.data(), &sizes);
  AccelerationStructure structure(context, type, sizes.accelerationStructureSize);

  // Scratch addresses need a stricter alignment than buffer memory may give: over-allocate, round up.
  const VkDeviceSize align =
      std::max<VkDeviceSize>(1, context.info().ray_tracing.min_acceleration_structure_scratch_offset_alignment);
  Buffer scratch(context, sizes.buildScratchSize + align,
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                 VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  build_info.dstAccelerationStructure = structure.handle();
  build_info.scratchData.deviceAddress = (scratch.address() + align - 1) / align * align;

  std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges(primitive_counts.size());
  for (size_t i = 0; i < ranges.size(); ++i) ranges[i].primitiveCount = primitive_counts[i];
  const VkAccelerationStructureBuildRangeInfoKHR* range_ptr = ranges.data();

  QueryPool query;
  if (options.compact) {
    VkQueryPoolCreateInfo create{};
    create.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    create.queryType = VK_QUERY_TYPE_ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR;
    create.queryCount = 1;
    VkQueryPool pool = VK_NULL_HANDLE;
    DHR_VK_CHECK(vkCreateQueryPool(device, &create, nullptr, &pool));
    query = QueryPool(device, pool);
  }

  AsBuildStats stats;
  stats.build_size = sizes.accelerationStructureSize;
  stats.scratch_size = sizes.buildScratchSize;
  for (uint32_t count : primitive_counts) stats.primitive_count += count;
  const auto build_start = std::chrono::steady_clock::now();
  context.submit_and_wait([&](VkCommandBuffer cmd) {
    if (query) vkCmdResetQueryPool(cmd, query.get(), 0, 1);
    // Inputs (vertices, instances) may have been written by earlier submissions.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, VK_ACCESS_2_SHADER_READ_BIT);
    rt.cmd_build_acceleration_structures(cmd, 1, &build_info, &range_ptr);
    after_build_barrier(cmd);
    if (query) {
      const VkAccelerationStructureKHR handle = structure.handle();
      rt.cmd_write_acceleration_structures_properties(
          cmd, 1, &handle, VK_QUERY_TYPE_ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR, query.get(), 0);
    }
  });
  stats.build_ms = elapsed_ms(build_start);

  if (query) {
    VkDeviceSize compacted = 0;
    DHR_VK_CHECK(vkGetQueryPoolResults(device, query.get(), 0, 1, sizeof compacted, &compacted, sizeof compacted,
                                       VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    if (compacted > 0 && compacted < sizes.accelerationStructureSize) {
      const auto compact_start = std::chrono::steady_clock::now();
      AccelerationStructure small(context, type, compacted);
      context.submit_and_wait([&](VkCommandBuffer cmd) {
        VkCopyAccelerationStructureInfoKHR copy{};
        copy.sType = VK_STRUCTURE_TYPE_COPY_ACCELERATION_STRUCTURE_INFO_KHR;
        copy.src = structure.handle();
        copy.dst = small.handle();
        copy.mode = VK_COPY_ACCELERATION_STRUCTURE_MODE_COMPACT_KHR;
        rt.cmd_copy_acceleration_structure(cmd, &copy);
        after_build_barrier(cmd);
      });
      structure = std::move(small);
      stats.compact_ms = elapsed_ms(compact_start);
    }
  }
  stats.final_size = structure.size();
  if (out_stats != nullptr) *out_stats = stats;
  return structure;
}

}  // namespace

AccelerationStructure::AccelerationStructure(const Context& context, VkAccelerationStructureTypeKHR type,
                                             VkDeviceSize size)
    : device_(context.device()), destroy_fn_(context.rt().destroy_acceleration_structure) {
  require_ray_tracing(context);
  buffer_ = Buffer(context, size,
                   VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                   VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VkAccelerationStructureCreateInfoKHR create{};
  create.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR;
  create.buffer = buffer_.handle();
  create.size = size;
  create.type = type;
  DHR_VK_CHECK(context.rt().create_acceleration_structure(device_, &create, nullptr, &handle_));
  VkAccelerationStructureDeviceAddressInfoKHR address{};
  address.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR;
  address.accelerationStructure = handle_;
  address_ = context.rt().get_acceleration_structure_device_address(device_, &address);
}

AccelerationStructure::~AccelerationStructure() { destroy(); }

AccelerationStructure::AccelerationStructure(AccelerationStructure&& other) noexcept { *this = std::move(other); }

AccelerationStructure& AccelerationStructure::operator=(AccelerationStructure&& other) noexcept {
  if (this != &other) {
    destroy();
    device_ = other.device_;
    destroy_fn_ = other.destroy_fn_;
    handle_ = std::exchange(other.handle_, VK_NULL_HANDLE);
    address_ = std::exchange(other.address_, 0);
    buffer_ = std::move(other.buffer_);
  }
  return *this;
}

void AccelerationStructure::destroy() {
  // The structure goes before the buffer that stores it.
  if (handle_ != VK_NULL_HANDLE) destroy_fn_(device_, handle_, nullptr);
  handle_ = VK_NULL_HANDLE;
  address_ = 0;
  buffer_ = Buffer();
}

AccelerationStructure build_blas(const Context& context, std::span<const TriangleGeometry> geometries,
                                 const AsBuildOptions& options, AsBuildStats* out_stats) {
  require_ray_tracing(context);
  if (geometries.empty()) throw std::invalid_argument("build_blas: no geometries");
  std::vector<VkAccelerationStructureGeometryKHR> geoms;
  std::vector<uint32_t> counts;
  for (const TriangleGeometry& g : geometries) {
    if (g.triangle_count == 0 || g.vertex_count == 0 || g.vertex_address == 0 || g.index_address == 0) {
      throw std::invalid_argument("build_blas: a geometry has no triangles, no vertices or no buffer address");
    }
    VkAccelerationStructureGeometryKHR geom{};
    geom.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR;
    geom.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
    geom.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
    VkAccelerationStructureGeometryTrianglesDataKHR& tri = geom.geometry.triangles;
    tri.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
    tri.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
    tri.vertexData.deviceAddress = g.vertex_address;
    tri.vertexStride = g.vertex_stride;
    tri.maxVertex = g.vertex_count - 1;
    tri.indexType = VK_INDEX_TYPE_UINT32;
    tri.indexData.deviceAddress = g.index_address;
    geoms.push_back(geom);
    counts.push_back(g.triangle_count);
  }
  return build(context, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, geoms, counts, options, out_stats);
}

AccelerationStructure build_blas(const Context& context, std::span<const float> positions_xyz,
                                 std::span<const uint32_t> indices, const AsBuildOptions& options,
                                 AsBuildStats* out_stats) {
  require_ray_tracing(context);
  if (positions_xyz.empty() || positions_xyz.size() % 3 != 0) {
    throw std::invalid_argument("build_blas: positions must hold x, y, z per vertex (got " +
                                std::to_string(positions_xyz.size()) + " floats)");
  }
  if (indices.empty() || indices.size() % 3 != 0) {
    throw std::invalid_argument("build_blas: indices must hold 3 per triangle (got " +
                                std::to_string(indices.size()) + ")");
  }
  const size_t vertex_count = positions_xyz.size() / 3;
  for (size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] >= vertex_count) {
      throw std::invalid_argument("build_blas: index " + std::to_string(i) + " = " + std::to_string(indices[i]) +
                                  " is out of range (" + std::to_string(vertex_count) + " vertices)");
    }
  }
  constexpr VkBufferUsageFlags kInput = VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
                                        VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  const Buffer vertices = create_buffer_with_data(context, positions_xyz, kInput);
  const Buffer index_buffer = create_buffer_with_data(context, indices, kInput);
  TriangleGeometry geometry;
  geometry.vertex_address = vertices.address();
  geometry.vertex_count = static_cast<uint32_t>(vertex_count);
  geometry.index_address = index_buffer.address();
  geometry.triangle_count = static_cast<uint32_t>(indices.size() / 3);
  return build_blas(context, std::span<const TriangleGeometry>(&geometry, 1), options, out_stats);
}

namespace {

// The instances as Vulkan records, in a buffer the build reads.
Buffer instance_buffer(const Context& context, std::span<const AsInstance> instances) {
  if (instances.empty()) throw std::invalid_argument("build_tlas: no instances");
  std::vector<VkAccelerationStructureInstanceKHR> records(instances.size());
  for (size_t i = 0; i < instances.size(); ++i) {
    const AsInstance& in = instances[i];
    if (in.blas == nullptr || !*in.blas) throw std::invalid_argument("build_tlas: instance without a BLAS");
    if (in.custom_index > kMax24Bit || in.sbt_offset > kMax24Bit) {
      throw std::invalid_argument("build_tlas: custom_index and sbt_offset must fit in 24 bits");
    }
    VkAccelerationStructureInstanceKHR& out = records[i];
    static_assert(sizeof(out.transform.matrix) == sizeof(in.transform));
    std::memcpy(out.transform.matrix, in.transform, sizeof(in.transform));
    out.instanceCustomIndex = in.custom_index;
    out.mask = in.mask;
    out.instanceShaderBindingTableRecordOffset = in.sbt_offset;
    out.flags = in.flags & 0xFFu;
    out.accelerationStructureReference = in.blas->address();
  }
  return create_buffer_with_data(
      context, std::span<const VkAccelerationStructureInstanceKHR>(records),
      VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT);
}

VkAccelerationStructureGeometryKHR instances_geometry(const Buffer& instances) {
  VkAccelerationStructureGeometryKHR geom{};
  geom.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR;
  geom.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  geom.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
  geom.geometry.instances.arrayOfPointers = VK_FALSE;
  geom.geometry.instances.data.deviceAddress = instances.address();
  return geom;
}

}  // namespace

AccelerationStructure build_tlas(const Context& context, std::span<const AsInstance> instances,
                                 const AsBuildOptions& options, AsBuildStats* out_stats) {
  require_ray_tracing(context);
  const Buffer records = instance_buffer(context, instances);
  return build(context, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, {instances_geometry(records)},
               {static_cast<uint32_t>(instances.size())}, options, out_stats);
}

void update_tlas(const Context& context, AccelerationStructure& tlas, std::span<const AsInstance> instances,
                 const AsBuildOptions& options, AsBuildStats* out_stats) {
  require_ray_tracing(context);
  if (!options.allow_update) throw std::logic_error("update_tlas: the TLAS was not built with allow_update");
  if (!tlas) throw std::logic_error("update_tlas: no TLAS");
  const RayTracingDispatch& rt = context.rt();
  const Buffer records = instance_buffer(context, instances);
  const VkAccelerationStructureGeometryKHR geom = instances_geometry(records);
  VkAccelerationStructureBuildGeometryInfoKHR info{};
  info.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR;
  info.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  info.flags = (options.prefer_fast_trace ? VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR
                                          : VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_BUILD_BIT_KHR) |
               VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_UPDATE_BIT_KHR |
               (options.compact ? VkBuildAccelerationStructureFlagsKHR{VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_COMPACTION_BIT_KHR}
                                : VkBuildAccelerationStructureFlagsKHR{0});
  info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR;
  info.geometryCount = 1;
  info.pGeometries = &geom;
  info.srcAccelerationStructure = tlas.handle();
  info.dstAccelerationStructure = tlas.handle();
  const uint32_t count = static_cast<uint32_t>(instances.size());
  VkAccelerationStructureBuildSizesInfoKHR sizes{};
  sizes.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR;
  rt.get_acceleration_structure_build_sizes(context.device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info,
                                            &count, &sizes);
  const VkDeviceSize align =
      std::max<VkDeviceSize>(1, context.info().ray_tracing.min_acceleration_structure_scratch_offset_alignment);
  Buffer scratch(context, std::max<VkDeviceSize>(sizes.updateScratchSize, 1) + align,
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                 VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  info.scratchData.deviceAddress = (scratch.address() + align - 1) / align * align;
  VkAccelerationStructureBuildRangeInfoKHR range{};
  range.primitiveCount = count;
  const VkAccelerationStructureBuildRangeInfoKHR* range_ptr = &range;
  const auto start = std::chrono::steady_clock::now();
  context.submit_and_wait([&](VkCommandBuffer cmd) {
    // The instance records were just uploaded; earlier traces may still read the structure.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT | VK_ACCESS_2_MEMORY_READ_BIT,
                   VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                   VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR);
    rt.cmd_build_acceleration_structures(cmd, 1, &info, &range_ptr);
    after_build_barrier(cmd);
  });
  if (out_stats != nullptr) {
    AsBuildStats stats;
    stats.build_ms = elapsed_ms(start);
    stats.build_size = stats.final_size = tlas.size();
    stats.scratch_size = sizes.updateScratchSize;
    stats.primitive_count = count;
    *out_stats = stats;
  }
}

}  // namespace dhr::vk
