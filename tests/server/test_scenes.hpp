// Hand-made scenes and analytic geometry for the server tests.
#pragma once
#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "visibility/visibility.hpp"

#include <glm/vec3.hpp>

#include <cstdint>

#include <optional>
#include <string>
#include <vector>

namespace dhr::test {

inline constexpr uint32_t kSingleSided = 0;  // material indices of make_empty_scene()
inline constexpr uint32_t kDoubleSided = 1;

// Two grey materials (single- and double-sided), no meshes, no lights.
Scene make_empty_scene();
// A quad split into n x n cells (2 triangles each): corner + a*u + b*v for a, b in [0, 1]; the front face
// (CCW, normals) points along cross(u, v).
void add_grid(Scene& scene, const glm::vec3& corner, const glm::vec3& u, const glm::vec3& v, uint32_t n,
              uint32_t material);
// Closed axis-aligned box with outward faces.
void add_box(Scene& scene, const glm::vec3& min, const glm::vec3& max, uint32_t material);
// Recomputes bounds and counts after adding meshes.
void finalize(Scene& scene);

SceneLight point_light(const glm::vec3& position, float intensity, float range = 0.0f);
SceneLight spot_light(const glm::vec3& position, const glm::vec3& direction, float inner_deg, float outer_deg,
                      float range = 0.0f);
SceneLight directional_light(const glm::vec3& direction, float lux = 3.0f);

// Pinhole camera (no guard band) at `eye` looking at `target` (+Y up), horizontal FOV in degrees.
Camera look_camera(const glm::dvec3& eye, const glm::dvec3& target, uint32_t width, uint32_t height,
                   double hfov_deg = 90.0);

// Light slots (more than 32 lights): an 8 x 8 m floor with 12 posts, and n x n point lights 1 m apart at 0.7 m, each
// reaching `range` (light 0 a 0.1 m sphere with soft_first); many_lights_camera looks down at it.
Scene many_lights_floor(int n, float range, bool soft_first = false);
Camera many_lights_camera(uint32_t width, uint32_t height);

// Analytic geometry in double. Entry distance of ray o + t d (t >= 0) into the box, if any.
std::optional<double> ray_box(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& min, const glm::dvec3& max);
// Whether the segment p -> q crosses the box.
bool segment_hits_box(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& min, const glm::dvec3& max);

// Left-eye cameras of a scene's bookmark file (90 degrees, the paper's guard band scaled to `eye`); a missing
// or malformed file fails the current test and gives none.
std::vector<Camera> bookmark_cameras(const std::string& scene_path, Extent eye);

// Loads a scene or fails the current test (returns an empty scene then).
Scene load_scene_or_fail(const std::string& path);

// The repository and shared-data paths (compile definitions).
std::string source_path(const std::string& relative);
// "" when ../shared/data is absent (tests that need it skip).
std::string shared_data_path(const std::string& relative);

// Pixels whose masks differ (UINT64_MAX when the buffers' shapes differ).
uint64_t differing_pixels(const VisibilityBuffer& a, const VisibilityBuffer& b);

}  // namespace dhr::test
