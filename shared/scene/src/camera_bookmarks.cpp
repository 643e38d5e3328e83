#include "scene/camera_bookmarks.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dhr {
namespace {

bool read_vec3(const nlohmann::json& value, glm::dvec3& out) {
  if (!value.is_array() || value.size() != 3) return false;
  for (int i = 0; i < 3; ++i) {
    if (!value[static_cast<size_t>(i)].is_number()) return false;
    out[i] = value[static_cast<size_t>(i)].get<double>();
    if (!std::isfinite(out[i]) || std::fabs(out[i]) > kMaxPositionMetres) return false;
  }
  return true;
}

bool parse_triplet(std::string_view text, glm::dvec3& out) {
  const std::string s(text);
  const char* p = s.c_str();
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    out[i] = std::strtod(p, &end);
    if (end == p || !std::isfinite(out[i]) || std::fabs(out[i]) > kMaxPositionMetres) return false;
    p = end;
    if (i < 2) {
      if (*p != ',') return false;
      ++p;
    }
  }
  return *p == '\0';
}

}  // namespace

std::string camera_bookmarks_path(const std::string& scene_path) {
  std::filesystem::path p(scene_path);
  p.replace_extension(".cameras.json");
  return p.string();
}

std::optional<std::vector<CameraBookmark>> load_camera_bookmarks(const std::string& path, std::string* out_error) {
  auto fail = [&](const std::string& problem) -> std::optional<std::vector<CameraBookmark>> {
    if (out_error) *out_error = path + ": " + problem;
    return std::nullopt;
  };
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail("cannot open the camera bookmark file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const nlohmann::json root = nlohmann::json::parse(buffer.str(), nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded()) return fail("not valid JSON");
  if (!root.is_object()) return fail("expected a JSON object");
  glm::dvec3 up(0.0, 1.0, 0.0);
  if (root.contains("up") && (!read_vec3(root["up"], up) || glm::length(up) == 0.0))
    return fail("\"up\" must be a non-zero array of 3 numbers");
  if (!root.contains("cameras") || !root["cameras"].is_array()) return fail("\"cameras\" must be an array");
  std::vector<CameraBookmark> out;
  const nlohmann::json& cameras = root["cameras"];
  for (size_t i = 0; i < cameras.size(); ++i) {
    const nlohmann::json& c = cameras[i];
    const std::string where = "cameras[" + std::to_string(i) + "]";
    if (!c.is_object()) return fail(where + ": expected an object");
    CameraBookmark b;
    b.up = glm::normalize(up);
    b.name = "camera" + std::to_string(i);
    if (c.contains("name")) {
      if (!c["name"].is_string()) return fail(where + ".name: expected a string");
      b.name = c["name"].get<std::string>();
    }
    if (!c.contains("position") || !read_vec3(c["position"], b.position))
      return fail(where + ".position: expected an array of 3 finite numbers");
    if (!c.contains("target") || !read_vec3(c["target"], b.target))
      return fail(where + ".target: expected an array of 3 finite numbers");
    if (!look_at_pose(b)) return fail(where + ": position equals target or the view is parallel to up");
    out.push_back(std::move(b));
  }
  if (out.empty()) return fail("no cameras");
  return out;
}

std::optional<CameraBookmark> parse_camera_spec(std::string_view spec, std::string* out_error) {
  auto fail = [&]() -> std::optional<CameraBookmark> {
    if (out_error) *out_error = "bad camera '" + std::string(spec) + "' (expected x,y,z:tx,ty,tz in metres)";
    return std::nullopt;
  };
  const size_t colon = spec.find(':');
  if (colon == std::string_view::npos) return fail();
  CameraBookmark b;
  if (!parse_triplet(spec.substr(0, colon), b.position) || !parse_triplet(spec.substr(colon + 1), b.target))
    return fail();
  if (!look_at_pose(b)) {
    if (out_error)
      *out_error = "bad camera '" + std::string(spec) + "': position equals target or looks straight up/down";
    return std::nullopt;
  }
  return b;
}

std::optional<Pose> look_at_pose(const CameraBookmark& bookmark) {
  const glm::dvec3 d = bookmark.target - bookmark.position;
  const double len = glm::length(d);
  if (!(len > 1e-9) || !(glm::length(bookmark.up) > 0.0)) return std::nullopt;
  const glm::dvec3 forward = d / len;
  const glm::dvec3 side = glm::cross(forward, glm::normalize(bookmark.up));
  if (!(glm::length(side) > 1e-6)) return std::nullopt;
  const glm::dvec3 right = glm::normalize(side);
  const glm::dvec3 up = glm::cross(right, forward);
  // Eye axes in world: +X right, +Y up, -Z forward (OpenXR).
  const glm::dmat3 world_from_eye(right, up, -forward);
  Pose pose;
  pose.position = bookmark.position;
  pose.orientation = glm::normalize(glm::quat_cast(world_from_eye));
  return pose;
}

Fov symmetric_fov(double horizontal_deg, Extent display) {
  const double half_h = horizontal_deg * 0.5 * 3.14159265358979323846 / 180.0;
  const double tan_v = std::tan(half_h) * display.height / display.width;
  const float h = static_cast<float>(half_h);
  const float v = static_cast<float>(std::atan(tan_v));
  return Fov{-h, h, v, -v};
}

Pose left_eye_pose(const Pose& head, double ipd_metres) {
  Pose eye = head;
  eye.position = head.transform_point(glm::dvec3(-0.5 * ipd_metres, 0.0, 0.0));
  return eye;
}

CameraBookmark front_bookmark(const SceneBounds& bounds) {
  // Half the vertical angle of that eye is ~29 degrees: sin = 0.49.
  const glm::dvec3 centre(bounds.center());
  const double radius = std::max(1e-3, 0.5 * static_cast<double>(bounds.diagonal()));
  CameraBookmark b;
  b.name = "bbox_front";
  b.position = centre + glm::normalize(glm::dvec3(0.0, 0.3, 1.0)) * (radius / 0.49);
  b.target = centre;
  return b;
}

}  // namespace dhr
