// Camera math of the client's passes, on the CPU in double. Camera-relative rendering: the GPU never sees
// world coordinates, only positions relative to the eye (rounded to float once, after a double subtraction),
// so a scene far from the origin keeps its precision (DESIGN.md, numerics).
//
// Depth convention (projection.hpp): reversed-Z with an infinite far plane, depth = near / distance along
// the view axis. A pixel position (px, py) (centres at +0.5) with depth d > 0 is the eye-space point
//   z = near / d,  (tx, ty) = camera.pixel_to_tangent(px, py),  p_eye = (tx * z, ty * z, -z),
// and the world point p_world = T_world_eye.position + R_world_eye * p_eye. This is the inverse of the
// camera-relative view-projection (projection * rotation-only view) applied to (ndc.x, ndc.y, d, 1),
// followed by adding the eye position in double; written out it needs no matrix inverse.
#pragma once
#include <array>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "math/projection.hpp"

namespace dhr::render {

// Near plane of the G-buffer's projection (metres).
inline constexpr double kDefaultNearPlane = kClipNearPlane;
// Points whose depth in the old eye is at or below this (metres) are "behind the old eye" in the warp.
inline constexpr double kWarpMinDepth = 1e-3;

// The display camera: the view's FOV over `extent` pixels, no guard band.
Camera display_camera(const View& view, Extent extent);

// projection(near) * rotation-only view (the eye at the origin), in double (MeshPush rounds it once).
glm::dmat4 camera_relative_view_projection(const Camera& camera, double near_plane);

// R_world_eye of the camera's pose (eye axes expressed in world axes).
glm::dmat3 eye_to_world_rotation(const Camera& camera);

// Eye-space point of a continuous pixel position with depth-buffer value `depth` (> 0).
glm::dvec3 eye_point_from_depth(const Camera& camera, double near_plane, double px, double py, double depth);
// World-space point of the same (see the header comment).
glm::dvec3 world_point_from_depth(const Camera& camera, double near_plane, double px, double py, double depth);

// False when a sphere (world centre, radius) lies entirely outside the camera's frustum (its four side
// planes and the eye plane; no far plane). Conservative: true when unsure.
bool sphere_may_be_visible(const Camera& camera, const glm::dvec3& centre, double radius);

// Column-major floats of a 4x4 matrix, for push constants.
std::array<float, 16> matrix_floats(const glm::mat4& m);

}  // namespace dhr::render
