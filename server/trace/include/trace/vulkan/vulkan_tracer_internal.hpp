// Internal to the Vulkan tracer (server/trace/src/vulkan/*.cpp; tests may use it): the CPU-side plan of the GPU scene,
// its upload into acceleration structures and storage buffers, and the ray-tracing pipeline.
#pragma once
#include "scene/lighting.hpp"
#include "shaders/shader_interface.h"
#include "trace/vulkan/vulkan_tracer.hpp"

#include "vk/acceleration_structure.hpp"
#include "vk/buffer.hpp"
#include "vk/context.hpp"
#include "vk/handle.hpp"
#include "vk/ray_tracing_pipeline.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace dhr::server::detail {

// Triangle order along a Morton (Z-order) curve through the triangles' centroids: out[i] is the original
// index of the i-th triangle in the new order. Ties keep the original order (deterministic).
// positions_xyz: x, y, z per vertex; indices: 3 per triangle, each < vertex count.
std::vector<uint32_t> morton_triangle_order(std::span<const float> positions_xyz, std::span<const uint32_t> indices);

// One bottom-level structure to build.
struct BlasPlan {
  std::vector<float> positions;     // x, y, z per vertex in the BLAS's space (local or scene-relative world)
  std::vector<uint32_t> indices;    // triangles in build order (spatially sorted when asked)
  uint32_t index_offset = 0;        // its triangles in original order: ScenePlan::indices from here
  uint32_t permutation_offset = 0;  // build order -> original triangle: ScenePlan::permutation from here
  bool mirrored = false;            // local -> world reverses orientation (negative determinant)
  // Instanced BLASes: positions = local - local_centre (the local bounding-box centre, so BLAS coordinates
  // stay small even when a file bakes large offsets into its vertices); instances add it back.
  glm::dvec3 local_centre{0.0};
};

// One TLAS instance: a SceneMesh placed with its BLAS.
struct InstancePlan {
  uint32_t mesh = 0;  // Scene::meshes index, the instance's custom index
  uint32_t blas = 0;  // ScenePlan::blases index
  float transform[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};  // BLAS space -> scene-relative world
  glm::dmat4 T_world_blas{1.0};  // BLAS space -> world (transform is this relative to ScenePlan::origin, in float)
  bool double_sided = false;
  bool mirrored = false;
};

// Everything the GPU scene holds, prepared on the CPU (no Vulkan).
struct ScenePlan {
  glm::dvec3 origin{0.0};  // world position of the scene-relative frame (bounding-box centre)
  std::vector<BlasPlan> blases;
  std::vector<InstancePlan> instances;
  std::vector<shader::VisMesh> meshes;  // one per Scene mesh (meshes without triangles are never hit)
  std::vector<float> positions;         // per mesh, scene-relative world, x, y, z per vertex
  std::vector<float> normals;           // per mesh, world, x, y, z per vertex (zero where missing)
  std::vector<uint32_t> indices;        // per BLAS, original triangle order, mesh-local vertex indices
  std::vector<uint32_t> permutation;    // per BLAS
  uint64_t triangles = 0;               // over all instances
  std::vector<uint32_t> moving;         // instances whose mesh is on a moving node (SceneAnimation::find)
};

// instance.transform from T_world_blas relative to `origin` (subtracted in double, then rounded).
void set_instance_transform(InstancePlan& instance, const glm::dmat4& T_world_blas, const glm::dvec3& origin);

// Each light prepared for sampling over its extent (make_sampled_light, as the Embree backend's soft fields), in the
// scene-relative frame whose world position is `origin`, with its scramble seed soft_seed(0, 0, light, salt)
// (SoftPattern::kPerLight, the only pattern the shader implements).
std::vector<shader::VisSoftLight> soft_light_records(std::span<const SceneLight> lights, const glm::dvec3& origin,
                                                     uint32_t salt);

// Validates the meshes (indices in range, finite positions) and plans BLASes and instances.
// Throws std::runtime_error naming the mesh and the problem.
ScenePlan plan_gpu_scene(const Scene& scene, const VulkanTracerConfig& config);

// The plan on the device. No TLAS when the scene has no triangles (every pixel is background).
struct GpuScene {
  vk::Buffer lights;  // PackedLight[] (at least one element: bindings need a non-empty buffer)
  vk::Buffer meshes;
  vk::Buffer positions;
  vk::Buffer normals;
  vk::Buffer indices;
  vk::Buffer permutation;
  vk::Buffer soft_lights;  // VisSoftLight[] (at least one element)
  vk::Buffer light_slots;  // LightSlots::gpu_words, scene-relative
  std::vector<vk::AccelerationStructure> blases;
  vk::AccelerationStructure tlas;
  std::vector<vk::AsInstance> instances;  // what the TLAS was built from (kept when it can be updated)
  vk::AsBuildOptions tlas_options;        // allow_update when the plan has moving instances
  AccelStats stats;  // build_ms covers the device work only (upload_gpu_scene's caller adds planning)
};

// Throws std::runtime_error when a buffer exceeds the device's maxStorageBufferRange.
GpuScene upload_gpu_scene(const vk::Context& context, const ScenePlan& plan, std::span<const PackedLight> lights,
                          std::span<const shader::VisSoftLight> soft_lights, std::span<const uint32_t> light_slots,
                          const VulkanTracerConfig& config);

// A mesh on a moving node, as the GPU scene holds it.
struct MovingMesh {
  uint32_t mesh = 0;             // Scene::meshes index
  uint32_t instance = 0;         // ScenePlan::instances / GpuScene::instances index
  glm::dmat4 T_world_blas{1.0};  // at rest
  glm::dmat4 motion{1.0};        // the motion last applied (mesh_motion_at)
  uint32_t vertex_offset = 0;    // its vertices in the positions and normals buffers
  std::vector<glm::vec3> rest_positions;  // world, at rest
  std::vector<glm::vec3> rest_normals;    // zero where the mesh has none
};

// What moves in the GPU scene and what mesh_motion_at and light_at read.
struct GpuMotion {
  Scene meta;                    // animation, lights at rest, meshes' node and T_world_local (no vertices)
  std::vector<MovingMesh> meshes;
  std::vector<SceneLight> lights;  // the lights at the scene time last applied
};

// Empty (no meshes, meta without animation) for a scene without animation.
GpuMotion plan_gpu_motion(const Scene& scene, const ScenePlan& plan);

struct GpuMotionUpdate {
  uint32_t moved_meshes = 0;
  uint64_t moved_vertices = 0;
  uint32_t moved_lights = 0;
  bool tlas_updated = false;
};

// Moves the GPU scene to scene time t (app-moved nodes where `overrides`, when given, puts them): each moving mesh whose motion changed gets its instance transform
// (motion * T_world_blas) and its shading vertices (moved_position, moved_normal: the floats the Embree backend
// traces), then one TLAS update over all instances; lights that moved are re-uploaded (packed and as soft records
// with `soft_salt`). Not concurrent with tracing.
GpuMotionUpdate move_gpu_scene(const vk::Context& context, GpuScene& gpu, GpuMotion& motion, const glm::dvec3& origin,
                               double t, const NodeOverrides* overrides, uint32_t soft_salt);

// The visibility pipeline with its single descriptor set.
struct TracerPipeline {
  vk::DescriptorSetLayout set_layout;
  vk::PipelineLayout layout;
  vk::DescriptorPool pool;
  VkDescriptorSet set = VK_NULL_HANDLE;  // freed with the pool
  vk::RayTracingPipeline pipeline;
};

TracerPipeline create_tracer_pipeline(const vk::Context& context);
// Binds the scene's TLAS and buffers (once, after the build).
void write_scene_descriptors(const vk::Context& context, const TracerPipeline& pipeline, const GpuScene& scene);
// Binds the per-frame outputs (after they are (re)allocated; never while a trace is in flight).
void write_frame_descriptors(const vk::Context& context, const TracerPipeline& pipeline, const vk::Buffer& masks,
                             const vk::Buffer& counters);

}  // namespace dhr::server::detail
