#include "render/mesh_push.hpp"

#include <algorithm>
#include <glm/mat3x3.hpp>

#include "render/client_scene.hpp"
#include "render/render_camera.hpp"
#include "scene/scene_at.hpp"

namespace dhr::render {

MeshPush::MeshPush(const glm::dmat4& view_proj, const glm::dvec3& eye)
    : view_proj_(view_proj), view_proj_floats_(matrix_floats(glm::mat4(view_proj))), eye_(eye) {}

void MeshPush::set(shader::ClientGBufferPush& push, const ClientMesh& mesh, const glm::dmat4* motion) const {
  if (motion == nullptr) {
    std::copy(view_proj_floats_.begin(), view_proj_floats_.end(), push.view_proj);
    const glm::vec3 t(mesh.origin - eye_);
    push.mesh[0] = t.x;
    push.mesh[1] = t.y;
    push.mesh[2] = t.z;
    for (int k = 3; k < 9; ++k) push.mesh[k] = 0.0f;
    push.flags &= ~shader::kClientMeshMoves;
    return;
  }
  // Mesh-relative vertex p -> world motion * (origin + p) -> eye-relative L p + (motion * origin - eye).
  glm::dmat4 model = *motion;
  model[3] = glm::dvec4(glm::dvec3(*motion * glm::dvec4(mesh.origin, 1.0)) - eye_, 1.0);
  const std::array<float, 16> mvp = matrix_floats(glm::mat4(view_proj_ * model));
  std::copy(mvp.begin(), mvp.end(), push.view_proj);
  const glm::dmat3 n = normal_matrix(*motion);
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) push.mesh[c * 3 + r] = static_cast<float>(n[c][r]);
  }
  push.flags |= shader::kClientMeshMoves;
}

}  // namespace dhr::render
