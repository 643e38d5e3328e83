#include "math/projection.hpp"

#include <cmath>

namespace dhr {

Tangents Tangents::from_fov(const Fov& fov) {
  return Tangents{std::tan(static_cast<double>(fov.angle_left)), std::tan(static_cast<double>(fov.angle_right)),
                  std::tan(static_cast<double>(fov.angle_up)), std::tan(static_cast<double>(fov.angle_down))};
}

Fov Tangents::to_fov() const {
  return Fov{static_cast<float>(std::atan(left)), static_cast<float>(std::atan(right)),
             static_cast<float>(std::atan(up)), static_cast<float>(std::atan(down))};
}

GuardBand scale_guard_band(GuardBand at_reference, Extent reference, Extent target) {
  auto scale = [](uint32_t band, uint32_t ref, uint32_t tgt) -> uint32_t {
    if (ref == 0) return 0;
    return static_cast<uint32_t>(std::lround(static_cast<double>(band) * tgt / ref));
  };
  return GuardBand{scale(at_reference.x, reference.width, target.width),
                   scale(at_reference.y, reference.height, target.height)};
}

GuardBand paper_guard_band(Extent display) {
  return scale_guard_band(GuardBand{32, 18}, Extent{1920, 1080}, display);
}

std::optional<GuardBand> guard_band_from_total(uint32_t total_x, uint32_t total_y) {
  if (total_x % 2 != 0 || total_y % 2 != 0) return std::nullopt;
  return GuardBand{total_x / 2, total_y / 2};
}

Camera Camera::with_guard_band(const View& view, Extent display, GuardBand guard) {
  Camera cam;
  cam.T_world_eye = view.pose;
  const Tangents t = Tangents::from_fov(view.fov);
  const double per_px_x = t.width() / display.width;
  const double per_px_y = t.height() / display.height;
  cam.tangents = Tangents{t.left - guard.x * per_px_x, t.right + guard.x * per_px_x, t.up + guard.y * per_px_y,
                          t.down - guard.y * per_px_y};
  cam.extent = Extent{display.width + 2 * guard.x, display.height + 2 * guard.y};
  return cam;
}

glm::dvec2 Camera::pixel_to_tangent(double px, double py) const {
  return {tangents.left + px / extent.width * tangents.width(),
          tangents.up - py / extent.height * tangents.height()};
}

glm::dvec2 Camera::tangent_to_pixel(double tx, double ty) const {
  return {(tx - tangents.left) / tangents.width() * extent.width,
          (tangents.up - ty) / tangents.height() * extent.height};
}

glm::dvec3 Camera::eye_ray(double px, double py) const {
  const glm::dvec2 t = pixel_to_tangent(px, py);
  return {t.x, t.y, -1.0};
}

glm::dvec3 Camera::world_ray(double px, double py) const {
  return glm::normalize(T_world_eye.orientation * eye_ray(px, py));
}

glm::dmat4 Camera::projection(double near_plane) const {
  const double w = tangents.width(), h = tangents.height();
  glm::dmat4 m(0.0);  // glm is column-major: m[column][row]
  m[0][0] = 2.0 / w;
  m[2][0] = (tangents.right + tangents.left) / w;
  m[1][1] = -2.0 / h;
  m[2][1] = -(tangents.up + tangents.down) / h;
  m[3][2] = near_plane;
  m[2][3] = -1.0;
  return m;
}

glm::dmat4 Camera::view_projection(double near_plane) const {
  return projection(near_plane) * T_world_eye.inverse_matrix();
}

Reprojection reproject(const Camera& camera, const glm::dvec3& p_world, double min_depth) {
  Reprojection out;
  // Eye-space point through the inverse pose, in double: no matrix round trip.
  const glm::dvec3 p_eye = glm::conjugate(camera.T_world_eye.orientation) * (p_world - camera.T_world_eye.position);
  out.depth = -p_eye.z;
  if (!(out.depth > min_depth)) {
    out.status = Reprojection::Status::kBehind;
    return out;
  }
  out.pixel = camera.tangent_to_pixel(p_eye.x / out.depth, p_eye.y / out.depth);
  const bool inside = out.pixel.x >= 0.0 && out.pixel.y >= 0.0 && out.pixel.x < camera.extent.width &&
                      out.pixel.y < camera.extent.height;
  out.status = inside ? Reprojection::Status::kInside : Reprojection::Status::kOutside;
  return out;
}

std::optional<std::string> validate_camera(const Camera& camera) {
  if (auto err = validate_pose(camera.T_world_eye)) return err;
  const Tangents& t = camera.tangents;
  if (!std::isfinite(t.left) || !std::isfinite(t.right) || !std::isfinite(t.up) || !std::isfinite(t.down))
    return "camera tangents are not finite";
  if (!(t.left < t.right) || !(t.down < t.up)) return "camera tangents are empty or inverted";
  if (camera.extent.width == 0 || camera.extent.height == 0) return "camera image size is zero";
  if (camera.extent.width > kMaxImageDimension || camera.extent.height > kMaxImageDimension)
    return "camera image size exceeds " + std::to_string(kMaxImageDimension) + " pixels per axis";
  return std::nullopt;
}

}  // namespace dhr
