// The eye model (head pose -> two eye views) and the placement of a trace's origin in a scene, for
// playing recorded head motion. docs/traces.md documents the defaults and the reasoning behind them.
#pragma once
#include "math/pose.hpp"
#include "traces/pose_trace.hpp"

#include <glm/vec3.hpp>

#include <array>
#include <optional>
#include <string>

namespace dhr {

inline constexpr double kDefaultEyeHeightMetres = 1.6;  // the scenes' camera files use it too

// Per-eye asymmetric FOV of a typical current standalone headset (representative values, not any
// vendor's calibration): 49 degrees towards the temple, 41 towards the nose, 44 up, 49 down. The
// tangent extents (2.020 x 2.116) have the aspect of a 1832x1920 panel: square pixels at that size.
Fov typical_headset_fov(int eye);  // 0 = left, 1 = right
// Monado's simulated HMD: 85 degrees across per eye, symmetric (vertical as measured, docs/xr-runtimes.md).
Fov monado_simulated_fov();

struct EyeModel {
  double ipd_metres = kDefaultIpdMetres;
  // Eyes relative to the head pose along the head's +Y (0: the head pose is at eye level, as OpenXR's
  // VIEW space and the datasets' HMD poses are).
  double eye_height_offset_metres = 0.0;
  std::array<Fov, 2> fov = {typical_headset_fov(0), typical_headset_fov(1)};

  static EyeModel typical_headset() { return {}; }
  static EyeModel monado_simulated();

  // The two eye views (0 = left) of a head pose: eyes at -+ipd/2 along the head's local +X, same
  // orientation as the head.
  std::array<View, 2> views(const Pose& T_world_head) const;
};

// Where a trace plays in a scene: T_scene_trace = translate(translation) * rotate_y(yaw) [* recentring].
// With recentre, the first head pose's position and yaw (heading about +Y; pitch and roll stay) are
// removed first, so the trace starts exactly at `translation`, facing `yaw`.
struct TracePlacement {
  glm::dvec3 translation{0.0, kDefaultEyeHeightMetres, 0.0};
  double yaw_radians = 0.0;  // about +Y, counter-clockwise seen from above; 0 faces -Z
  bool recentre = true;
};

// Heading about +Y of a pose's forward (-Z) axis: 0 when facing -Z, positive when turned left (towards
// -X). Falls back to the up axis when looking straight up or down.
double yaw_of(const glm::dquat& orientation);

// A placement that starts the trace at a scene camera: at `position`, facing the heading of target.
TracePlacement placement_from_camera(const glm::dvec3& position, const glm::dvec3& target);

// The scene's default placement: the first camera of "<scene without extension>.cameras.json" beside the
// scene when that file exists and is usable, otherwise TracePlacement{} (head at 1.6 m over the origin,
// facing -Z). out_note (optional) says which one was taken and why.
TracePlacement default_trace_placement(const std::string& scene_path, std::string* out_note = nullptr);

// T_scene_trace for a placement, given the trace's first head pose (used only with recentre).
Pose placement_transform(const TracePlacement& placement, const Pose& first_head);

// The two eye views of a trace sample placed in the scene: the recorded eye poses and FOVs when the
// trace has them, the eye model otherwise.
std::array<View, 2> trace_views(const PoseTrace& trace, const TraceSample& sample, const EyeModel& eyes,
                                const Pose& T_scene_trace);

}  // namespace dhr
