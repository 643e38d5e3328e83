#include "render/render_camera.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

namespace dhr::render {

Camera display_camera(const View& view, Extent extent) { return Camera::with_guard_band(view, extent, GuardBand{}); }

glm::dmat3 eye_to_world_rotation(const Camera& camera) { return glm::mat3_cast(camera.T_world_eye.orientation); }

glm::dmat4 camera_relative_view_projection(const Camera& camera, double near_plane) {
  const glm::dmat4 eye_from_world_axes(glm::transpose(eye_to_world_rotation(camera)));
  return camera.projection(near_plane) * eye_from_world_axes;
}

glm::dvec3 eye_point_from_depth(const Camera& camera, double near_plane, double px, double py, double depth) {
  const glm::dvec2 t = camera.pixel_to_tangent(px, py);
  const double z = near_plane / depth;
  return {t.x * z, t.y * z, -z};
}

glm::dvec3 world_point_from_depth(const Camera& camera, double near_plane, double px, double py, double depth) {
  return camera.T_world_eye.position +
         eye_to_world_rotation(camera) * eye_point_from_depth(camera, near_plane, px, py, depth);
}

bool sphere_may_be_visible(const Camera& camera, const glm::dvec3& centre, double radius) {
  const glm::dvec3 c = glm::conjugate(camera.T_world_eye.orientation) * (centre - camera.T_world_eye.position);
  const Tangents& t = camera.tangents;
  // Inward plane normals through the eye (eye space: +X right, +Y up, -Z forward).
  const glm::dvec3 planes[5] = {{1.0, 0.0, t.left}, {-1.0, 0.0, -t.right}, {0.0, -1.0, -t.up},
                                {0.0, 1.0, t.down}, {0.0, 0.0, -1.0}};
  const double margin = 1e-6 * (glm::length(c) + radius) + 1e-6;
  for (const glm::dvec3& n : planes) {
    if (glm::dot(n, c) / glm::length(n) < -(radius + margin)) return false;
  }
  return true;
}

std::array<float, 16> matrix_floats(const glm::mat4& m) {
  std::array<float, 16> out{};
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) out[static_cast<size_t>(c * 4 + r)] = m[c][r];
  }
  return out;
}

}  // namespace dhr::render
