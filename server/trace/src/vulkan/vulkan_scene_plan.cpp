// CPU side of the Vulkan tracer's scene: validation, instancing, spatial triangle order, shading buffers.
#include "trace/vulkan/vulkan_tracer_internal.hpp"

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace dhr::server::detail {
namespace {

// Spreads the low 21 bits of v to every third bit of a 63-bit value.
uint64_t spread_bits_3(uint64_t v) {
  v &= 0x1FFFFFu;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

void check_mesh(const SceneMesh& mesh) {
  const size_t index_count = mesh.indices.size() / 3 * 3;
  for (size_t i = 0; i < index_count; ++i) {
    if (mesh.indices[i] >= mesh.positions.size())
      throw std::runtime_error("vulkan tracer: mesh '" + mesh.name + "': index " + std::to_string(mesh.indices[i]) +
                               " out of range (" + std::to_string(mesh.positions.size()) + " vertices)");
  }
  for (const glm::vec3& p : mesh.positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw std::runtime_error("vulkan tracer: mesh '" + mesh.name + "': non-finite vertex position");
  }
  if (mesh.positions.size() > std::numeric_limits<uint32_t>::max() / 3 ||
      mesh.indices.size() > std::numeric_limits<uint32_t>::max())
    throw std::runtime_error("vulkan tracer: mesh '" + mesh.name + "' is too large");
}

// The mesh's linear part can be inverted to recover its local vertices.
bool invertible(const glm::dmat4& T) {
  const double det = glm::determinant(glm::dmat3(T));
  if (!std::isfinite(det) || std::abs(det) < 1e-18) return false;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(T[c][r])) return false;
  return true;
}

uint32_t checked_u32(size_t value, const char* what) {
  if (value > std::numeric_limits<uint32_t>::max())
    throw std::runtime_error(std::string("vulkan tracer: scene too large (") + what + " exceed 32-bit offsets)");
  return static_cast<uint32_t>(value);
}

// Adds one BLAS from the given (BLAS-space) positions and the mesh's indices.
uint32_t add_blas(ScenePlan& plan, std::vector<float> positions, const SceneMesh& mesh, bool mirrored,
                  bool morton_sort, const glm::dvec3& local_centre = glm::dvec3(0.0)) {
  const size_t tri_count = mesh.triangle_count();
  const std::span<const uint32_t> original(mesh.indices.data(), tri_count * 3);
  BlasPlan blas;
  blas.mirrored = mirrored;
  blas.local_centre = local_centre;
  blas.index_offset = checked_u32(plan.indices.size(), "indices");
  blas.permutation_offset = checked_u32(plan.permutation.size(), "triangles");
  plan.indices.insert(plan.indices.end(), original.begin(), original.end());
  std::vector<uint32_t> order;
  if (morton_sort) {
    order = morton_triangle_order(positions, original);
  } else {
    order.resize(tri_count);
    for (uint32_t t = 0; t < tri_count; ++t) order[t] = t;
  }
  blas.indices.resize(tri_count * 3);
  for (size_t t = 0; t < tri_count; ++t)
    for (size_t k = 0; k < 3; ++k) blas.indices[3 * t + k] = original[3 * size_t{order[t]} + k];
  plan.permutation.insert(plan.permutation.end(), order.begin(), order.end());
  blas.positions = std::move(positions);
  plan.blases.push_back(std::move(blas));
  return static_cast<uint32_t>(plan.blases.size() - 1);
}

}  // namespace

void set_instance_transform(InstancePlan& instance, const glm::dmat4& T_world_blas, const glm::dvec3& origin) {
  glm::dmat4 T = T_world_blas;
  T[3] -= glm::dvec4(origin, 0.0);  // into the scene-relative frame, in double
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) instance.transform[r][c] = static_cast<float>(T[c][r]);
}

std::vector<uint32_t> morton_triangle_order(std::span<const float> positions_xyz, std::span<const uint32_t> indices) {
  const size_t tri_count = indices.size() / 3;
  std::vector<glm::vec3> centroids(tri_count);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (size_t t = 0; t < tri_count; ++t) {
    glm::vec3 c(0.0f);
    for (size_t k = 0; k < 3; ++k) {
      const size_t v = indices[3 * t + k];
      c += glm::vec3(positions_xyz[3 * v], positions_xyz[3 * v + 1], positions_xyz[3 * v + 2]);
    }
    centroids[t] = c / 3.0f;
    lo = glm::min(lo, centroids[t]);
    hi = glm::max(hi, centroids[t]);
  }
  // 21 bits per axis over the centroids' bounding box (a flat axis maps to 0).
  constexpr double kCells = double((1u << 21) - 1);
  std::vector<std::pair<uint64_t, uint32_t>> keyed(tri_count);
  for (size_t t = 0; t < tri_count; ++t) {
    uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double extent = double(hi[a]) - double(lo[a]);
      const double x = extent > 0.0 ? (double(centroids[t][a]) - double(lo[a])) / extent : 0.0;
      code |= spread_bits_3(static_cast<uint64_t>(std::clamp(x, 0.0, 1.0) * kCells)) << a;
    }
    keyed[t] = {code, static_cast<uint32_t>(t)};
  }
  std::sort(keyed.begin(), keyed.end());  // (code, original index): a total, deterministic order
  std::vector<uint32_t> order(tri_count);
  for (size_t t = 0; t < tri_count; ++t) order[t] = keyed[t].second;
  return order;
}

ScenePlan plan_gpu_scene(const Scene& scene, const VulkanTracerConfig& config) {
  ScenePlan plan;
  plan.origin = scene.bounds.empty() ? glm::dvec3(0.0)
                                     : glm::dvec3(scene.bounds.min) * 0.5 + glm::dvec3(scene.bounds.max) * 0.5;
  plan.meshes.resize(scene.meshes.size());
  // (geometry, mirrored) -> BLAS shared by the instances, and the mesh whose indices it was built from.
  std::map<std::pair<uint32_t, bool>, std::pair<uint32_t, const SceneMesh*>> shared;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const SceneMesh& mesh = scene.meshes[m];
    check_mesh(mesh);
    shader::VisMesh& record = plan.meshes[m];
    record.vertex_offset = checked_u32(plan.positions.size() / 3, "vertices");
    const bool double_sided = mesh.material < scene.materials.size() && scene.materials[mesh.material].double_sided;
    record.flags = double_sided ? shader::kVisMeshDoubleSided : 0u;
    // Shading data in the frame the shaders work in: positions relative to the origin (subtracted in double).
    for (const glm::vec3& p : mesh.positions) {
      const glm::vec3 r(glm::dvec3(p) - plan.origin);
      plan.positions.insert(plan.positions.end(), {r.x, r.y, r.z});
    }
    const bool has_normals = mesh.normals.size() == mesh.positions.size();
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const glm::vec3 n = has_normals ? mesh.normals[v] : glm::vec3(0.0f);
      plan.normals.insert(plan.normals.end(), {n.x, n.y, n.z});
    }
    const size_t tri_count = mesh.triangle_count();
    if (tri_count == 0 || mesh.positions.empty()) continue;
    plan.triangles += tri_count;

    InstancePlan instance;
    instance.mesh = static_cast<uint32_t>(m);
    instance.double_sided = double_sided;
    const bool can_instance = config.instanced && invertible(mesh.T_world_local);
    uint32_t blas = 0;
    if (can_instance) {
      const bool mirrored = glm::determinant(glm::dmat3(mesh.T_world_local)) < 0.0;
      const auto key = std::make_pair(mesh.geometry, mirrored);
      auto it = shared.find(key);
      // The mesh's local vertices (the world ones brought back through its transform), about their box's centre.
      const glm::dmat4 T_local_world = glm::inverse(mesh.T_world_local);
      std::vector<glm::dvec3> q(mesh.positions.size());
      glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
      for (size_t v = 0; v < q.size(); ++v) {
        q[v] = glm::dvec3(T_local_world * glm::dvec4(glm::dvec3(mesh.positions[v]), 1.0));
        lo = glm::min(lo, q[v]);
        hi = glm::max(hi, q[v]);
      }
      const glm::dvec3 centre = lo * 0.5 + hi * 0.5;
      std::vector<float> local;
      local.reserve(q.size() * 3);
      for (const glm::dvec3& p : q) {
        const glm::vec3 r(p - centre);
        local.insert(local.end(), {r.x, r.y, r.z});
      }
      // Instances of one glTF primitive share a BLAS: same indices and the same local vertices (up to the rounding
      // of bringing world vertices back: 1e-5 of the box). A mesh whose SceneMesh::geometry merely collides (a scene
      // built in code) gets its own.
      const SceneMesh* built_from = it == shared.end() ? nullptr : it->second.second;
      bool reuse = built_from != nullptr && built_from->positions.size() == mesh.positions.size() &&
                   built_from->triangle_count() == tri_count &&
                   std::equal(mesh.indices.begin(), mesh.indices.begin() + tri_count * 3, built_from->indices.begin());
      if (reuse) {
        const BlasPlan& candidate = plan.blases[it->second.first];
        const double tolerance = 1e-5 * glm::length(hi - lo) + 1e-9;
        reuse = glm::length(candidate.local_centre - centre) <= tolerance;
        for (size_t i = 0; reuse && i < local.size(); ++i)
          reuse = std::abs(double(candidate.positions[i]) - double(local[i])) <= tolerance;
      }
      if (reuse) {
        blas = it->second.first;
      } else {
        blas = add_blas(plan, std::move(local), mesh, mirrored, config.morton_sort, centre);
        if (it == shared.end()) shared.emplace(key, std::make_pair(blas, &mesh));
      }
      instance.mirrored = mirrored;
      instance.T_world_blas = glm::translate(mesh.T_world_local, plan.blases[blas].local_centre);
      set_instance_transform(instance, instance.T_world_blas, plan.origin);
    } else {
      // World-space BLAS (the scene-relative positions above), identity instance.
      const auto first = plan.positions.end() - static_cast<std::ptrdiff_t>(mesh.positions.size() * 3);
      blas = add_blas(plan, std::vector<float>(first, plan.positions.end()), mesh, false, config.morton_sort);
      instance.T_world_blas = glm::translate(glm::dmat4(1.0), plan.origin);
    }
    if (scene.animation.find(mesh.node) != nullptr) plan.moving.push_back(static_cast<uint32_t>(plan.instances.size()));
    instance.blas = blas;
    record.index_offset = plan.blases[blas].index_offset;
    record.permutation_offset = plan.blases[blas].permutation_offset;
    plan.instances.push_back(instance);
  }
  return plan;
}

}  // namespace dhr::server::detail
