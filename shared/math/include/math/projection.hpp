// Pinhole cameras from OpenXR's asymmetric FOV, guard bands, and reprojection.
//
// Conventions: eye space is right-handed, +X right, +Y up, -Z forward (OpenXR). Images are row-major,
// pixel (0,0) at the top-left, pixel centres at (i + 0.5, j + 0.5). Clip space is Vulkan's: x right,
// y down, depth in [0,1], reversed-Z with an infinite far plane (depth = near / distance along -Z).
#pragma once
#include "math/pose.hpp"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace dhr {

// tan() of the four FOV angles: left and down are usually negative.
struct Tangents {
  double left = -1.0;
  double right = 1.0;
  double up = 1.0;
  double down = -1.0;

  static Tangents from_fov(const Fov& fov);
  Fov to_fov() const;
  double width() const { return right - left; }
  double height() const { return up - down; }
};

struct Extent {
  uint32_t width = 0;
  uint32_t height = 0;
  bool operator==(const Extent&) const = default;
};

// Extra pixels on each side of the displayed region: x on the left and on the right, y at the top and at the
// bottom (the traced image is display + 2 * guard). The wire protocol uses the same convention.
struct GuardBand {
  uint32_t x = 0;
  uint32_t y = 0;
  bool operator==(const GuardBand&) const = default;
};

// Scales a guard band given for a reference display size to another size, rounding to whole pixels per side.
GuardBand scale_guard_band(GuardBand at_reference, Extent reference, Extent target);
// The paper's guard band (1984x1116 traced for 1920x1080: 32x18 per side) scaled to a display size.
GuardBand paper_guard_band(Extent display);
// A guard band given as total extra pixels per axis (the paper's "+64x36", command lines): std::nullopt when
// a total is odd (the band is the same on both sides).
std::optional<GuardBand> guard_band_from_total(uint32_t total_x, uint32_t total_y);

// A pinhole camera: where the eye is, its (possibly guard-banded) tangents, and the image size.
struct Camera {
  Pose T_world_eye;
  Tangents tangents;
  Extent extent;

  // The display camera widened by a guard band: same focal length (pixels per tangent unit), extent grows by
  // the band on each side, tangents by the band's share.
  static Camera with_guard_band(const View& view, Extent display, GuardBand guard);

  // Pixels per unit tangent along x and y.
  double focal_x() const { return extent.width / tangents.width(); }
  double focal_y() const { return extent.height / tangents.height(); }

  // Tangent-space point (x/-z, y/-z) of continuous pixel coordinates (pixel centres at +0.5).
  glm::dvec2 pixel_to_tangent(double px, double py) const;
  glm::dvec2 tangent_to_pixel(double tx, double ty) const;

  // Unnormalized eye-space ray direction through a pixel position (z = -1).
  glm::dvec3 eye_ray(double px, double py) const;
  // World-space unit ray direction through a pixel position.
  glm::dvec3 world_ray(double px, double py) const;

  // Vulkan projection (reversed-Z, infinite far) for eye space; near > 0.
  glm::dmat4 projection(double near_plane) const;
  // projection * eye_from_world.
  glm::dmat4 view_projection(double near_plane) const;
};

// What the server traces for each eye of a session: the displayed size plus a guard band. The one place that
// turns a view into the camera its visibility buffer is traced (and looked up) with.
struct TracedFormat {
  Extent display;   // displayed size per eye (no guard band)
  GuardBand guard;  // per side

  Extent buffer() const { return Extent{display.width + 2 * guard.x, display.height + 2 * guard.y}; }
  Camera camera(const View& view) const { return Camera::with_guard_band(view, display, guard); }
  bool operator==(const TracedFormat&) const = default;
};

// Where a world-space point lands in a camera's image.
struct Reprojection {
  enum class Status {
    kInside,   // in front of the eye and inside the image
    kOutside,  // in front of the eye, outside the image
    kBehind,   // at or behind the eye plane (w <= epsilon): no valid image position
  };
  Status status = Status::kBehind;
  glm::dvec2 pixel{0.0};  // continuous pixel coordinates (valid unless kBehind)
  double depth = 0.0;     // distance along the view axis (-z in eye space)
};

// Projects p (world space) into the camera. Points with eye-space depth <= min_depth are kBehind.
Reprojection reproject(const Camera& camera, const glm::dvec3& p_world, double min_depth = 1e-6);

// The client rasterizes nothing nearer than this (metres along the view axis: its G-buffer's near plane), and
// the server's primary rays start there, so both see the same surface at every pixel.
inline constexpr double kClipNearPlane = 0.05;

// Returns an error message when the camera cannot be used (bad pose/FOV, zero or absurd extent).
inline constexpr uint32_t kMaxImageDimension = 16384;
std::optional<std::string> validate_camera(const Camera& camera);

}  // namespace dhr
