// Device side of the Vulkan tracer's scene: compacted BLASes, the TLAS and the shading storage buffers.
#include "trace/vulkan/vulkan_tracer_internal.hpp"

#include "log/log.hpp"

#include <chrono>
#include <stdexcept>
#include <string>

namespace dhr::server::detail {
namespace {

// Vulkan, like glTF, calls a triangle front-facing when it is counter-clockwise seen from the ray origin
// (right-handed). Facing is decided in object space, so an instance whose transform mirrors (the loader
// swapped its indices to keep world-space fronts counter-clockwise) needs FLIP_FACING. Checked against the
// Embree backend by tests/vulkan/vulkan_tracer_test.cpp (plain, rotated and mirrored instances).
constexpr VkGeometryInstanceFlagsKHR kMirroredFacing = VK_GEOMETRY_INSTANCE_TRIANGLE_FLIP_FACING_BIT_KHR;

template <typename T>
vk::Buffer storage_buffer(const vk::Context& context, const std::vector<T>& data, VkDeviceSize max_range,
                          const char* what) {
  const VkDeviceSize bytes = data.size() * sizeof(T);
  if (bytes > max_range)
    throw std::runtime_error(std::string("vulkan tracer: the scene's ") + what + " need " + std::to_string(bytes) +
                             " bytes, more than the device's storage-buffer range (" + std::to_string(max_range) +
                             "); use the embree backend or a smaller scene");
  if (data.empty()) {
    const T zero[4]{};  // bindings need a non-empty buffer; never read
    return vk::create_buffer_with_data(context, std::span<const T>(zero, 4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  }
  return vk::create_buffer_with_data(context, std::span<const T>(data), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
}

}  // namespace

GpuScene upload_gpu_scene(const vk::Context& context, const ScenePlan& plan, std::span<const PackedLight> lights,
                          std::span<const shader::VisSoftLight> soft_lights, std::span<const uint32_t> light_slots,
                          const VulkanTracerConfig& config) {
  const auto t0 = std::chrono::steady_clock::now();
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(context.physical_device(), &properties);
  const VkDeviceSize max_range = properties.limits.maxStorageBufferRange;

  GpuScene gpu;
  gpu.lights = storage_buffer(context, std::vector<PackedLight>(lights.begin(), lights.end()), max_range, "lights");
  gpu.soft_lights = storage_buffer(context, std::vector<shader::VisSoftLight>(soft_lights.begin(), soft_lights.end()),
                                   max_range, "light extents");
  gpu.light_slots = storage_buffer(context, std::vector<uint32_t>(light_slots.begin(), light_slots.end()), max_range,
                                   "light slots");
  gpu.meshes = storage_buffer(context, plan.meshes, max_range, "mesh records");
  gpu.positions = storage_buffer(context, plan.positions, max_range, "vertex positions");
  gpu.normals = storage_buffer(context, plan.normals, max_range, "vertex normals");
  gpu.indices = storage_buffer(context, plan.indices, max_range, "indices");
  gpu.permutation = storage_buffer(context, plan.permutation, max_range, "triangle permutation");
  const double upload_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  vk::AsBuildOptions options;
  options.compact = config.compact;
  options.prefer_fast_trace = true;
  double blas_ms = 0.0, compact_ms = 0.0;
  VkDeviceSize bytes = 0, uncompacted = 0;
  gpu.blases.reserve(plan.blases.size());
  for (const BlasPlan& blas : plan.blases) {
    vk::AsBuildStats stats;
    gpu.blases.push_back(vk::build_blas(context, blas.positions, blas.indices, options, &stats));
    blas_ms += stats.build_ms;
    compact_ms += stats.compact_ms;
    bytes += stats.final_size;
    uncompacted += stats.build_size;
  }
  if (!plan.instances.empty()) {
    std::vector<vk::AsInstance>& instances = gpu.instances;
    instances.resize(plan.instances.size());
    for (size_t i = 0; i < instances.size(); ++i) {
      const InstancePlan& in = plan.instances[i];
      vk::AsInstance& out = instances[i];
      out.blas = &gpu.blases[in.blas];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) out.transform[r][c] = in.transform[r][c];
      out.custom_index = in.mesh;
      out.mask = 0xFF;
      out.sbt_offset = 0;
      // Back faces are culled only by primary rays (gl_RayFlagsCullBackFacingTrianglesEXT); double-sided
      // meshes opt out here. Shadow rays do not cull, so the facing flag only matters to primary rays.
      if (in.double_sided) {
        out.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
      } else if (in.mirrored) {
        out.flags = kMirroredFacing;
      }
    }
    vk::AsBuildStats stats;
    gpu.tlas_options = options;
    gpu.tlas_options.allow_update = !plan.moving.empty();  // moving instances: updated in place per scene time
    gpu.tlas = vk::build_tlas(context, instances, gpu.tlas_options, &stats);
    blas_ms += stats.build_ms;
    compact_ms += stats.compact_ms;
    bytes += stats.final_size;
    uncompacted += stats.build_size;
  }
  gpu.stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  gpu.stats.bytes = bytes;
  gpu.stats.triangles = plan.triangles;
  gpu.stats.blas_count = static_cast<uint32_t>(plan.blases.size());
  gpu.stats.instance_count = static_cast<uint32_t>(plan.instances.size());
  log::info("vulkan tracer: %u BLAS + TLAS over %u instances, %llu triangles: %.1f ms (uploads %.1f, builds %.1f, "
            "compaction %.1f), %.2f MiB (%.2f MiB before compaction)",
            gpu.stats.blas_count, gpu.stats.instance_count, static_cast<unsigned long long>(plan.triangles),
            gpu.stats.build_ms, upload_ms, blas_ms, compact_ms, double(bytes) / (1 << 20),
            double(uncompacted) / (1 << 20));
  return gpu;
}

}  // namespace dhr::server::detail
