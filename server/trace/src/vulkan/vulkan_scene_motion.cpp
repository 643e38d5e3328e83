// The Vulkan tracer's scene time: moving meshes keep their BLAS (built at rest) and move by their instance transform,
// updated in place in the TLAS; their shading vertices (which the raygen shader rebuilds the surface point from) are
// rewritten with the same floats the Embree backend traces; moved lights are re-uploaded.
#include "trace/vulkan/vulkan_tracer_internal.hpp"

#include "scene/scene_at.hpp"

#include <stdexcept>
#include <string>

namespace dhr::server::detail {

GpuMotion plan_gpu_motion(const Scene& scene, const ScenePlan& plan) {
  GpuMotion motion;
  if (scene.animation.empty()) return motion;
  motion.meta.animation = scene.animation;
  motion.meta.lights = scene.lights;
  motion.lights = scene.lights;
  motion.meta.meshes.reserve(scene.meshes.size());
  for (const SceneMesh& mesh : scene.meshes) {
    SceneMesh& meta = motion.meta.meshes.emplace_back();
    meta.name = mesh.name;
    meta.node = mesh.node;
    meta.T_world_local = mesh.T_world_local;
  }
  for (const uint32_t i : plan.moving) {
    const InstancePlan& instance = plan.instances[i];
    const SceneMesh& mesh = scene.meshes[instance.mesh];
    MovingMesh& moving = motion.meshes.emplace_back();
    moving.mesh = instance.mesh;
    moving.instance = i;
    moving.T_world_blas = instance.T_world_blas;
    moving.vertex_offset = plan.meshes[instance.mesh].vertex_offset;
    moving.rest_positions = mesh.positions;
    moving.rest_normals = mesh.normals.size() == mesh.positions.size()
                              ? mesh.normals
                              : std::vector<glm::vec3>(mesh.positions.size(), glm::vec3(0.0f));
  }
  return motion;
}

GpuMotionUpdate move_gpu_scene(const vk::Context& context, GpuScene& gpu, GpuMotion& motion, const glm::dvec3& origin,
                               double t, const NodeOverrides* overrides, uint32_t soft_salt) {
  GpuMotionUpdate update;
  if (motion.meta.animation.empty()) return update;
  std::vector<float> positions, normals;
  for (MovingMesh& m : motion.meshes) {
    const glm::dmat4 T = mesh_motion_at(motion.meta, motion.meta.meshes[m.mesh], t, overrides);
    if (T == m.motion) continue;
    m.motion = T;
    InstancePlan placed;
    set_instance_transform(placed, T * m.T_world_blas, origin);
    vk::AsInstance& instance = gpu.instances.at(m.instance);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) instance.transform[r][c] = placed.transform[r][c];
    // The shading vertices at t, as EmbreeScene::set_scene_time writes them.
    const glm::dmat3 nm = normal_matrix(T);
    positions.clear();
    normals.clear();
    for (size_t v = 0; v < m.rest_positions.size(); ++v) {
      const glm::vec3 p(glm::dvec3(moved_position(T, m.rest_positions[v])) - origin);
      const glm::vec3 n = moved_normal(nm, m.rest_normals[v]);
      positions.insert(positions.end(), {p.x, p.y, p.z});
      normals.insert(normals.end(), {n.x, n.y, n.z});
    }
    const VkDeviceSize offset = VkDeviceSize{m.vertex_offset} * 3 * sizeof(float);
    vk::upload_to_buffer(context, gpu.positions, positions.data(), positions.size() * sizeof(float), offset);
    vk::upload_to_buffer(context, gpu.normals, normals.data(), normals.size() * sizeof(float), offset);
    ++update.moved_meshes;
    update.moved_vertices += m.rest_positions.size();
  }
  if (update.moved_meshes > 0 && gpu.tlas) {
    vk::update_tlas(context, gpu.tlas, gpu.instances, gpu.tlas_options);
    update.tlas_updated = true;
  }

  bool lights_changed = false;
  for (size_t i = 0; i < motion.lights.size(); ++i) {
    const SceneLight moved = light_at(motion.meta, motion.meta.lights[i], t, overrides);
    if (moved.position == motion.lights[i].position && moved.direction == motion.lights[i].direction &&
        moved.tangent == motion.lights[i].tangent && moved.bitangent == motion.lights[i].bitangent)
      continue;
    motion.lights[i] = moved;
    lights_changed = true;
    ++update.moved_lights;
  }
  if (lights_changed) {
    const std::vector<PackedLight> packed = pack_lights(motion.lights, origin);
    vk::upload_to_buffer(context, gpu.lights, packed.data(), packed.size() * sizeof(PackedLight));
    const std::vector<shader::VisSoftLight> soft = soft_light_records(motion.lights, origin, soft_salt);
    if (!soft.empty())
      vk::upload_to_buffer(context, gpu.soft_lights, soft.data(), soft.size() * sizeof(shader::VisSoftLight));
  }
  return update;
}

}  // namespace dhr::server::detail
