#include "traces/eye_model.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

namespace dhr {

namespace {

constexpr double kDegrees = std::numbers::pi / 180.0;

float radians(double degrees) { return static_cast<float>(degrees * kDegrees); }

glm::dquat rotation_about_y(double angle) { return glm::angleAxis(angle, glm::dvec3(0.0, 1.0, 0.0)); }

// Reads the first camera's position and target; false with the reason otherwise.
bool read_first_camera(const std::string& path, glm::dvec3* out_position, glm::dvec3* out_target,
                       std::string* out_reason) {
  std::ifstream in(path);
  if (!in) {
    *out_reason = "cannot open";
    return false;
  }
  const nlohmann::json doc = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded() || !doc.is_object()) {
    *out_reason = "not a JSON object";
    return false;
  }
  const auto cameras = doc.find("cameras");
  if (cameras == doc.end() || !cameras->is_array() || cameras->empty() || !(*cameras)[0].is_object()) {
    *out_reason = "no 'cameras' array with a first camera";
    return false;
  }
  const nlohmann::json& camera = (*cameras)[0];
  auto read_vec3 = [&](const char* key, glm::dvec3* out) {
    const auto v = camera.find(key);
    if (v == camera.end() || !v->is_array() || v->size() != 3) return false;
    for (int i = 0; i < 3; ++i) {
      if (!(*v)[i].is_number()) return false;
      (*out)[i] = (*v)[i].get<double>();
      if (!std::isfinite((*out)[i]) || std::fabs((*out)[i]) > kMaxPositionMetres) return false;
    }
    return true;
  };
  if (!read_vec3("position", out_position) || !read_vec3("target", out_target)) {
    *out_reason = "the first camera needs finite 'position' and 'target' arrays of 3 numbers";
    return false;
  }
  return true;
}

}  // namespace

Fov typical_headset_fov(int eye) {
  Fov fov;
  const bool left = eye == 0;
  fov.angle_left = radians(left ? -49.0 : -41.0);
  fov.angle_right = radians(left ? 41.0 : 49.0);
  fov.angle_up = radians(44.0);
  fov.angle_down = radians(-49.0);
  return fov;
}

Fov monado_simulated_fov() {
  // simulated_hmd.c: 85 degrees across per eye on a 0.065 x 0.07 m half panel, lens centred, so the
  // vertical half-angle has tangent tan(42.5 deg) * 0.07 / 0.065 (0.7788 rad).
  const double half_h = 42.5 * kDegrees;
  const double half_v = std::atan(std::tan(half_h) * 0.07 / 0.065);
  Fov fov;
  fov.angle_left = static_cast<float>(-half_h);
  fov.angle_right = static_cast<float>(half_h);
  fov.angle_up = static_cast<float>(half_v);
  fov.angle_down = static_cast<float>(-half_v);
  return fov;
}

EyeModel EyeModel::monado_simulated() {
  EyeModel model;
  model.fov = {monado_simulated_fov(), monado_simulated_fov()};
  return model;
}

std::array<View, 2> EyeModel::views(const Pose& T_world_head) const {
  std::array<View, 2> out;
  for (int i = 0; i < 2; ++i) {
    Pose T_head_eye;
    T_head_eye.position = glm::dvec3((i == 0 ? -0.5 : 0.5) * ipd_metres, eye_height_offset_metres, 0.0);
    out[i].pose = normalized(T_world_head * T_head_eye);
    out[i].fov = fov[i];
  }
  return out;
}

double yaw_of(const glm::dquat& orientation) {
  const glm::dquat q = glm::normalize(orientation);
  glm::dvec3 axis = q * glm::dvec3(0.0, 0.0, -1.0);
  // Looking straight up or down, the heading is where the top of the head points (or away from it).
  if (std::hypot(axis.x, axis.z) < 1e-9) axis = q * glm::dvec3(0.0, axis.y > 0.0 ? -1.0 : 1.0, 0.0);
  // rotate_y(a) * (0,0,-1) = (-sin a, 0, -cos a)
  return std::atan2(-axis.x, -axis.z);
}

TracePlacement placement_from_camera(const glm::dvec3& position, const glm::dvec3& target) {
  TracePlacement placement;
  placement.translation = position;
  const glm::dvec3 d = target - position;
  placement.yaw_radians = std::hypot(d.x, d.z) > 1e-9 ? std::atan2(-d.x, -d.z) : 0.0;
  placement.recentre = true;
  return placement;
}

TracePlacement default_trace_placement(const std::string& scene_path, std::string* out_note) {
  std::filesystem::path cameras = scene_path;
  cameras.replace_extension(".cameras.json");
  std::string note;
  TracePlacement placement;
  std::error_code ec;
  if (!std::filesystem::exists(cameras, ec)) {
    note = "no " + cameras.string() + ": trace placed at 1.6 m over the origin, facing -Z";
  } else {
    glm::dvec3 position(0.0);
    glm::dvec3 target(0.0);
    std::string reason;
    if (read_first_camera(cameras.string(), &position, &target, &reason)) {
      placement = placement_from_camera(position, target);
      note = "trace placed at the first camera of " + cameras.string();
    } else {
      note = cameras.string() + ": " + reason + "; trace placed at 1.6 m over the origin, facing -Z";
    }
  }
  if (out_note != nullptr) *out_note = note;
  return placement;
}

Pose placement_transform(const TracePlacement& placement, const Pose& first_head) {
  Pose T_scene_placed;
  T_scene_placed.position = placement.translation;
  T_scene_placed.orientation = rotation_about_y(placement.yaw_radians);
  if (!placement.recentre) return T_scene_placed;
  // Recentring: the first head pose's position goes to the origin, its heading to -Z.
  Pose T_placed_trace;
  T_placed_trace.orientation = rotation_about_y(-yaw_of(first_head.orientation));
  T_placed_trace.position = -(T_placed_trace.orientation * first_head.position);
  return normalized(T_scene_placed * T_placed_trace);
}

std::array<View, 2> trace_views(const PoseTrace& trace, const TraceSample& sample, const EyeModel& eyes,
                                const Pose& T_scene_trace) {
  std::array<View, 2> out = eyes.views(T_scene_trace * sample.head);
  if (trace.has_eye_poses) {
    for (int i = 0; i < 2; ++i) out[i].pose = normalized(T_scene_trace * sample.eye[i]);
  }
  if (trace.has_fov) {
    for (int i = 0; i < 2; ++i) out[i].fov = sample.fov[i];
  }
  return out;
}

}  // namespace dhr
