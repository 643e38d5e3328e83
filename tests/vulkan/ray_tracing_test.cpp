// Ray-tracing smoke test: BLAS + TLAS (compacted) of a few triangles in two visible instances and one
// masked-out instance, traced by the ray-tracing pipeline over a 64x64 orthographic grid, compared
// with a double-precision Moller-Trumbore reference on the CPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "dhr_shaders_smoke.hpp"
#include "shaders/smoke_interface.h"
#include "vk/acceleration_structure.hpp"
#include "vk/buffer.hpp"
#include "vk/pipeline.hpp"
#include "vk/ray_tracing_pipeline.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::vk {
namespace {

using shader::SmokeHit;
using shader::SmokePushConstants;
using RayTracingSmokeTest = test::RayTracingTest;

constexpr uint32_t kGrid = 64;
constexpr double kEdgeEpsilon = 1e-4;  // barycentric distance below which a ray is ambiguous
constexpr double kRelativeT = 1e-4;

// Five triangles at different depths, two of them tilted (object space).
const std::vector<float> kPositions = {
    -1.0f, -1.0f, 0.0f,  1.0f, -1.0f, 0.0f,  0.0f, 1.0f, 0.0f,   // 0: z = 0
    -0.5f, -0.5f, 0.5f,  0.5f, -0.5f, 0.5f,  0.0f, 0.6f, 0.5f,   // 1: z = 0.5, in front of 0
    0.2f, 0.2f, 1.0f,    0.9f, 0.3f, 1.0f,   0.4f, 0.9f, 1.0f,   // 2: z = 1
    -0.9f, 0.1f, -0.3f,  -0.2f, 0.2f, -0.6f, -0.6f, 0.8f, -0.4f, // 3: tilted, behind 0
    0.3f, -0.9f, 0.8f,   0.9f, -0.8f, 0.2f,  0.6f, -0.2f, 0.5f,  // 4: tilted, crosses z = 0.5
};
const std::vector<uint32_t> kIndices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14};

using Transform = std::array<std::array<float, 4>, 3>;

struct SceneInstance {
  Transform transform;
  uint32_t custom_index;
  uint8_t mask;
};

// Instance B: scale 0.8, rotate 30 degrees about x then 90 degrees about z, move to (1.5, 0.5, -2).
Transform instance_b_transform() {
  const double c = std::cos(std::numbers::pi / 6.0);
  const double s = std::sin(std::numbers::pi / 6.0);
  // Rz(90) * Rx(30) = [[0, -c, s], [1, 0, 0], [0, s, c]]
  const double r[3][3] = {{0.0, -c, s}, {1.0, 0.0, 0.0}, {0.0, s, c}};
  const double t[3] = {1.5, 0.5, -2.0};
  Transform m{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m[i][j] = static_cast<float>(0.8 * r[i][j]);
    m[i][3] = static_cast<float>(t[i]);
  }
  return m;
}

std::vector<SceneInstance> scene_instances() {
  const Transform identity = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
  // A half-size copy in front of part of instance A.
  const Transform in_front = {{{0.5f, 0, 0, -0.8f}, {0, 0.5f, 0, -0.8f}, {0, 0, 0.5f, 3.0f}}};
  return {
      {identity, 7, 0x01},
      {instance_b_transform(), 11, 0x01},
      {in_front, 99, 0x02},  // in front of everything: visible only when the cull mask has bit 1
  };
}

SmokePushConstants push_constants(uint32_t cull_mask) {
  SmokePushConstants pc{};
  pc.grid_min_x = -1.5f;
  pc.grid_min_y = -1.5f;
  pc.step_x = 4.0f / kGrid;
  pc.step_y = 3.0f / kGrid;
  pc.origin_z = 10.0f;
  pc.t_min = 0.0f;
  pc.t_max = 100.0f;
  pc.width = kGrid;
  pc.height = kGrid;
  pc.cull_mask = cull_mask;
  return pc;
}

struct Expected {
  bool ambiguous = false;
  bool hit = false;
  double t = 0.0;
  uint32_t primitive_id = 0;
  uint32_t custom_index = 0;
};

using Vec3 = std::array<double, 3>;
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Closest hit of one ray against every instance the cull mask admits (Moller-Trumbore in double).
Expected reference_hit(const std::vector<SceneInstance>& instances, const SmokePushConstants& pc, uint32_t x,
                       uint32_t y) {
  // Same float arithmetic as the raygen shader for the origin, then double from there on.
  const Vec3 origin = {pc.grid_min_x + (static_cast<float>(x) + 0.5f) * pc.step_x,
                       pc.grid_min_y + (static_cast<float>(y) + 0.5f) * pc.step_y, pc.origin_z};
  const Vec3 dir = {0.0, 0.0, -1.0};
  Expected best;
  double second_t = INFINITY;
  for (const SceneInstance& inst : instances) {
    if ((inst.mask & pc.cull_mask) == 0) continue;
    for (uint32_t tri = 0; tri < kIndices.size() / 3; ++tri) {
      Vec3 v[3];
      for (int k = 0; k < 3; ++k) {
        const float* p = &kPositions[3 * kIndices[3 * tri + k]];
        for (int i = 0; i < 3; ++i) {
          v[k][i] = double{inst.transform[i][0]} * double{p[0]} + double{inst.transform[i][1]} * double{p[1]} +
                    double{inst.transform[i][2]} * double{p[2]} + double{inst.transform[i][3]};
        }
      }
      const Vec3 e1 = sub(v[1], v[0]);
      const Vec3 e2 = sub(v[2], v[0]);
      const Vec3 p = cross(dir, e2);
      const double det = dot(e1, p);
      if (std::fabs(det) < 1e-12) continue;  // parallel to the ray
      const Vec3 s = sub(origin, v[0]);
      const double u = dot(s, p) / det;
      const Vec3 q = cross(s, e1);
      const double w = dot(dir, q) / det;
      const double t = dot(e2, q) / det;
      const double nearest_edge = std::min({u, w, 1.0 - u - w});
      if (std::fabs(nearest_edge) < kEdgeEpsilon) best.ambiguous = true;  // grazes an edge
      if (nearest_edge < 0.0 || t < double{pc.t_min} || t > double{pc.t_max}) continue;
      if (!best.hit || t < best.t) {
        second_t = best.hit ? best.t : second_t;
        best.hit = true;
        best.t = t;
        best.primitive_id = tri;
        best.custom_index = inst.custom_index;
      } else {
        second_t = std::min(second_t, t);
      }
    }
  }
  // Two surfaces at (almost) the same distance: either may legitimately win.
  if (best.hit && second_t - best.t < kRelativeT * best.t) best.ambiguous = true;
  return best;
}

struct SmokeRig {
  AccelerationStructure blas;
  AccelerationStructure tlas;
  AsBuildStats blas_stats;
  AsBuildStats tlas_stats;
};

SmokeRig build_scene(const Context& context) {
  SmokeRig rig;
  rig.blas = build_blas(context, kPositions, kIndices, AsBuildOptions{}, &rig.blas_stats);
  std::vector<AsInstance> instances;
  for (const SceneInstance& s : scene_instances()) {
    AsInstance inst;
    inst.blas = &rig.blas;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 4; ++j) inst.transform[i][j] = s.transform[i][j];
    }
    inst.custom_index = s.custom_index;
    inst.mask = s.mask;
    instances.push_back(inst);
  }
  rig.tlas = build_tlas(context, instances, AsBuildOptions{}, &rig.tlas_stats);
  return rig;
}

std::vector<SmokeHit> trace_grid(const Context& context, const AccelerationStructure& tlas, uint32_t cull_mask) {
  const VkDevice device = context.device();
  const VkDescriptorSetLayoutBinding bindings[] = {
      {shader::kSmokeBindingTlas, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, 1, VK_SHADER_STAGE_RAYGEN_BIT_KHR,
       nullptr},
      {shader::kSmokeBindingResults, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_RAYGEN_BIT_KHR, nullptr},
  };
  const DescriptorSetLayout set_layout = create_descriptor_set_layout(device, bindings);
  const VkPushConstantRange push{VK_SHADER_STAGE_RAYGEN_BIT_KHR, 0, sizeof(SmokePushConstants)};
  const VkDescriptorSetLayout set_layouts[] = {set_layout.get()};
  const PipelineLayout layout = create_pipeline_layout(device, set_layouts, std::span(&push, 1));

  const auto modules = dhr_shaders_smoke_modules();
  RayTracingPipelineDesc desc;
  desc.raygen = &find_spirv(modules, "smoke.rgen");
  desc.miss = {&find_spirv(modules, "smoke.rmiss")};
  desc.hit_groups = {{&find_spirv(modules, "smoke.rchit"), nullptr}};
  desc.layout = layout.get();
  const RayTracingPipeline pipeline(context, desc);

  const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, 1},
                                        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1}};
  const DescriptorPool pool = create_descriptor_pool(device, 1, sizes);
  const VkDescriptorSet set = allocate_descriptor_set(device, pool.get(), set_layout.get());
  Buffer results(context, sizeof(SmokeHit) * kGrid * kGrid,
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                 VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  write_acceleration_structure_descriptor(device, set, shader::kSmokeBindingTlas, tlas.handle());
  write_buffer_descriptor(device, set, shader::kSmokeBindingResults, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                          results.handle());

  const SmokePushConstants pc = push_constants(cull_mask);
  context.submit_and_wait([&](VkCommandBuffer cmd) {
    pipeline.bind(cmd);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, layout.get(), 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, layout.get(), VK_SHADER_STAGE_RAYGEN_BIT_KHR, 0, sizeof pc, &pc);
    pipeline.trace(cmd, kGrid, kGrid);
  });
  std::vector<SmokeHit> hits(kGrid * kGrid);
  read_buffer(context, results, hits.data(), results.size());
  return hits;
}

void compare_with_reference(const std::vector<SmokeHit>& hits, uint32_t cull_mask) {
  const std::vector<SceneInstance> instances = scene_instances();
  const SmokePushConstants pc = push_constants(cull_mask);
  int compared = 0;
  int skipped = 0;
  int hit_count = 0;
  int per_instance[3] = {0, 0, 0};
  for (uint32_t y = 0; y < kGrid; ++y) {
    for (uint32_t x = 0; x < kGrid; ++x) {
      const Expected want = reference_hit(instances, pc, x, y);
      if (want.ambiguous) {
        ++skipped;
        continue;
      }
      ++compared;
      const SmokeHit& got = hits[y * kGrid + x];
      ASSERT_EQ(got.hit, want.hit ? 1u : 0u) << "ray (" << x << ", " << y << ")";
      if (!want.hit) continue;
      ++hit_count;
      ASSERT_EQ(got.primitive_id, want.primitive_id) << "ray (" << x << ", " << y << ")";
      ASSERT_EQ(got.custom_index, want.custom_index) << "ray (" << x << ", " << y << ")";
      ASSERT_NEAR(double{got.t}, want.t, kRelativeT * want.t) << "ray (" << x << ", " << y << ")";
      per_instance[want.custom_index == 7 ? 0 : want.custom_index == 11 ? 1 : 2]++;
    }
  }
  // The comparison must be meaningful: most rays compared, hits on both visible instances, misses too.
  EXPECT_LT(skipped, static_cast<int>(kGrid * kGrid / 50)) << "too many ambiguous rays";
  EXPECT_GT(per_instance[0], 50);
  EXPECT_GT(per_instance[1], 50);
  EXPECT_GT(compared - hit_count, 50);
  EXPECT_EQ(per_instance[2] > 0, (cull_mask & 0x02) != 0);
}

TEST_F(RayTracingSmokeTest, TracedGridMatchesCpuReference) {
  const SmokeRig rig = build_scene(ctx());
  EXPECT_EQ(rig.blas_stats.primitive_count, 5u);
  EXPECT_EQ(rig.tlas_stats.primitive_count, 3u);
  EXPECT_GT(rig.blas_stats.final_size, 0u);
  EXPECT_LE(rig.blas_stats.final_size, rig.blas_stats.build_size);
  EXPECT_LE(rig.tlas_stats.final_size, rig.tlas_stats.build_size);
  EXPECT_EQ(rig.blas.size(), rig.blas_stats.final_size);
  EXPECT_NE(rig.tlas.address(), 0u);
  compare_with_reference(trace_grid(ctx(), rig.tlas, 0x01), 0x01);  // instance 99 masked out
  compare_with_reference(trace_grid(ctx(), rig.tlas, 0x03), 0x03);  // instance 99 in front
}

TEST_F(RayTracingSmokeTest, UncompactedBuildAlsoWorks) {
  AsBuildOptions options;
  options.compact = false;
  AsBuildStats stats;
  const AccelerationStructure blas = build_blas(ctx(), kPositions, kIndices, options, &stats);
  EXPECT_EQ(stats.final_size, stats.build_size);
  EXPECT_EQ(stats.compact_ms, 0.0);
  EXPECT_NE(blas.address(), 0u);
}

TEST_F(RayTracingSmokeTest, BadGeometryFailsClearly) {
  const std::vector<uint32_t> out_of_range = {0, 1, 5};
  const std::vector<float> three_vertices(kPositions.begin(), kPositions.begin() + 9);
  EXPECT_THROW(build_blas(ctx(), three_vertices, out_of_range), std::invalid_argument);
  EXPECT_THROW(build_blas(ctx(), three_vertices, std::vector<uint32_t>{0, 1}), std::invalid_argument);
  EXPECT_THROW(build_blas(ctx(), std::vector<float>{1.0f, 2.0f}, kIndices), std::invalid_argument);
  EXPECT_THROW(build_tlas(ctx(), std::vector<AsInstance>{AsInstance{}}), std::invalid_argument);
  AsInstance too_big;
  const AccelerationStructure blas = build_blas(ctx(), three_vertices, std::vector<uint32_t>{0, 1, 2});
  too_big.blas = &blas;
  too_big.custom_index = 1u << 24;
  EXPECT_THROW(build_tlas(ctx(), std::vector<AsInstance>{too_big}), std::invalid_argument);
}

using NoRayTracingTest = test::VulkanTest;

TEST_F(NoRayTracingTest, AccelerationStructuresNeedRayTracing) {
  EXPECT_THROW(build_blas(ctx(), kPositions, kIndices), std::logic_error);
}

}  // namespace
}  // namespace dhr::vk
