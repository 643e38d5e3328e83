// Poses, fields of view and views, in the OpenXR conventions (right-handed, +Y up, -Z forward;
// XrFovf angles in radians, left/down negative). Composed in double on the CPU.
#pragma once
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace dhr {

// Interpupillary distance (metres) of the eye models, snapshots and benchmarks: the adult median, also Monado's
// OXR_DEBUG_IPD_MM default.
inline constexpr double kDefaultIpdMetres = 0.063;

// T_world_eye: the eye expressed in world coordinates (position + Hamilton unit quaternion).
struct Pose {
  glm::dvec3 position{0.0};
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};  // glm order: w, x, y, z

  glm::dmat4 matrix() const;          // world_from_eye
  glm::dmat4 inverse_matrix() const;  // eye_from_world
  Pose operator*(const Pose& rhs) const;  // composition: (this) o (rhs)
  Pose inverse() const;
  glm::dvec3 transform_point(const glm::dvec3& p) const;
};

// Asymmetric field of view, as XrFovf (radians; angle_left and angle_down are usually negative).
struct Fov {
  float angle_left = -0.785398f;
  float angle_right = 0.785398f;
  float angle_up = 0.785398f;
  float angle_down = -0.785398f;
};

struct View {
  Pose pose;
  Fov fov;
};

// One client frame's pose: its number, its predicted display time, both eyes' views ([0] = left) and the scene
// time of its display. Pose sources produce it, the frame loop renders it, the planner keeps it in its history.
struct FramePose {
  uint64_t frame = 0;
  int64_t display_time_ns = 0;  // predicted display time (OpenXR XrTime, or virtual time from 0)
  std::array<View, 2> views{};
  // The scene clock at that display (DESIGN 5b): nanoseconds since the session's start, >= 0; animations play on
  // it. Virtual-clock sources use display_time_ns itself; OpenXR sources count from their first frame's display.
  int64_t scene_time_ns = 0;
};

// Returns an error message when the pose is unusable (non-finite values, a zero quaternion or one too large to
// normalize, |position| > kMaxPositionMetres); otherwise std::nullopt.
inline constexpr double kMaxPositionMetres = 1.0e6;
std::optional<std::string> validate_pose(const Pose& pose);
std::optional<std::string> validate_fov(const Fov& fov);
// The one check of a view before it is used (pose and FOV): pose sources' output is checked here by the
// client's PoseGuard, and every view decoded from the wire by the protocol decoder.
std::optional<std::string> validate_view(const View& view);

// Renormalizes the orientation (call after composing or decoding). Requires a non-zero quaternion.
Pose normalized(const Pose& pose);

}  // namespace dhr
