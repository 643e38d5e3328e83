#include "test_scenes.hpp"

#include "scene/camera_bookmarks.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <filesystem>
#include <limits>

namespace dhr::test {

Scene make_empty_scene() {
  Scene scene;
  scene.source = "test";
  SceneMaterial single;
  single.name = "single";
  single.base_color_factor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  SceneMaterial both = single;
  both.name = "double";
  both.double_sided = true;
  scene.materials = {single, both};
  return scene;
}

void add_grid(Scene& scene, const glm::vec3& corner, const glm::vec3& u, const glm::vec3& v, uint32_t n,
              uint32_t material) {
  SceneMesh mesh;
  mesh.name = "grid" + std::to_string(scene.meshes.size());
  mesh.material = material;
  mesh.geometry = static_cast<uint32_t>(scene.meshes.size());
  const glm::vec3 normal = glm::normalize(glm::cross(u, v));
  for (uint32_t j = 0; j <= n; ++j) {
    for (uint32_t i = 0; i <= n; ++i) {
      mesh.positions.push_back(corner + u * (static_cast<float>(i) / static_cast<float>(n)) +
                               v * (static_cast<float>(j) / static_cast<float>(n)));
      mesh.normals.push_back(normal);
    }
  }
  for (uint32_t j = 0; j < n; ++j) {
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
    }
  }
  scene.meshes.push_back(std::move(mesh));
}

void add_box(Scene& scene, const glm::vec3& lo, const glm::vec3& hi, uint32_t material) {
  const glm::vec3 s = hi - lo;
  add_grid(scene, {lo.x, hi.y, hi.z}, {s.x, 0, 0}, {0, 0, -s.z}, 1, material);  // +y
  add_grid(scene, {lo.x, lo.y, lo.z}, {s.x, 0, 0}, {0, 0, s.z}, 1, material);   // -y
  add_grid(scene, {hi.x, lo.y, hi.z}, {0, 0, -s.z}, {0, s.y, 0}, 1, material);  // +x
  add_grid(scene, {lo.x, lo.y, lo.z}, {0, 0, s.z}, {0, s.y, 0}, 1, material);   // -x
  add_grid(scene, {lo.x, lo.y, hi.z}, {s.x, 0, 0}, {0, s.y, 0}, 1, material);   // +z
  add_grid(scene, {hi.x, lo.y, lo.z}, {-s.x, 0, 0}, {0, s.y, 0}, 1, material);  // -z
}

void finalize(Scene& scene) {
  scene.bounds = SceneBounds{};
  scene.triangle_count = 0;
  scene.vertex_count = 0;
  for (const SceneMesh& m : scene.meshes) {
    for (const glm::vec3& p : m.positions) scene.bounds.extend(p);
    scene.triangle_count += m.triangle_count();
    scene.vertex_count += m.positions.size();
  }
}

SceneLight point_light(const glm::vec3& position, float intensity, float range) {
  SceneLight l;
  l.type = SceneLight::Type::kPoint;
  l.name = "point";
  l.position = position;
  l.intensity = intensity;
  l.range = range;
  return l;
}

SceneLight spot_light(const glm::vec3& position, const glm::vec3& direction, float inner_deg, float outer_deg,
                      float range) {
  SceneLight l;
  l.type = SceneLight::Type::kSpot;
  l.name = "spot";
  l.position = position;
  l.direction = glm::normalize(direction);
  l.intensity = 20.0f;
  l.range = range;
  l.inner_cone = glm::radians(inner_deg);
  l.outer_cone = glm::radians(outer_deg);
  return l;
}

SceneLight directional_light(const glm::vec3& direction, float lux) {
  SceneLight l;
  l.type = SceneLight::Type::kDirectional;
  l.name = "sun";
  l.direction = glm::normalize(direction);
  l.intensity = lux;
  return l;
}

Camera look_camera(const glm::dvec3& eye, const glm::dvec3& target, uint32_t width, uint32_t height,
                   double hfov_deg) {
  CameraBookmark b;
  b.position = eye;
  b.target = target;
  const auto pose = look_at_pose(b);
  const Extent extent{width, height};
  return Camera::with_guard_band(View{pose.value(), symmetric_fov(hfov_deg, extent)}, extent, GuardBand{});
}

Scene many_lights_floor(int n, float range, bool soft_first) {
  Scene s = make_empty_scene();
  add_grid(s, glm::vec3(-1, 0, -1), glm::vec3(0, 0, 9), glm::vec3(9, 0, 0), 9, kSingleSided);
  for (int i = 0; i < 12; ++i) {  // posts 0.25 m beside some lights (which stand at whole metres), taller than them
    const float x = 0.25f + static_cast<float>(i * 3 % 7), z = static_cast<float>(i * 5 % 7);
    add_box(s, glm::vec3(x - 0.05f, 0.0f, z - 0.1f), glm::vec3(x + 0.05f, 1.0f, z + 0.1f), kSingleSided);
  }
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x)
      s.lights.push_back(point_light(glm::vec3(static_cast<float>(x), 0.7f, static_cast<float>(z)), 5.0f, range));
  if (soft_first) s.lights[0].radius = 0.1f;
  finalize(s);
  return s;
}

Camera many_lights_camera(uint32_t width, uint32_t height) {
  return look_camera(glm::dvec3(3.5, 4.5, 7.0), glm::dvec3(3.5, 0.0, 3.0), width, height);
}

std::optional<double> ray_box(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi) {
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return std::nullopt;
      continue;
    }
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return std::nullopt;
  }
  return t0;
}

bool segment_hits_box(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& lo, const glm::dvec3& hi) {
  const auto t = ray_box(p, q - p, lo, hi);
  return t && *t <= 1.0;
}

std::string source_path(const std::string& relative) { return std::string(DHR_SOURCE_DIR) + "/" + relative; }

std::string shared_data_path(const std::string& relative) {
  const std::string dir = DHR_SHARED_DATA_DIR;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return "";
  // Only what is there: a partial copy of the data (scripts/gpu-run's bundle) skips the tests of what it lacks.
  const std::string path = dir + "/" + relative;
  return std::filesystem::exists(path, ec) ? path : "";
}

std::vector<Camera> bookmark_cameras(const std::string& scene_path, Extent eye) {
  std::string error;
  auto bookmarks = load_camera_bookmarks(camera_bookmarks_path(scene_path), &error);
  EXPECT_TRUE(bookmarks) << error;
  std::vector<Camera> cameras;
  if (!bookmarks) return cameras;
  const GuardBand guard = paper_guard_band(eye);
  for (const CameraBookmark& b : *bookmarks) {
    const View view{left_eye_pose(look_at_pose(b).value()), symmetric_fov(90.0, eye)};
    cameras.push_back(Camera::with_guard_band(view, eye, guard));
  }
  return cameras;
}

Scene load_scene_or_fail(const std::string& path) {
  SceneLoadResult loaded = load_scene(path);
  EXPECT_TRUE(loaded) << loaded.error;
  return loaded ? std::move(*loaded.scene) : Scene{};
}

uint64_t differing_pixels(const VisibilityBuffer& a, const VisibilityBuffer& b) {
  if (a.width != b.width || a.height != b.height || a.light_count != b.light_count) return UINT64_MAX;
  uint64_t n = 0;
  for (size_t i = 0; i < a.pixel_count(); ++i) n += a.mask_at(i) != b.mask_at(i);
  return n;
}

}  // namespace dhr::test
