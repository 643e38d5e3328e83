// Fuzz target: load_scene_from_memory on arbitrary bytes (.gltf JSON text or .glb; the loader tells
// them apart by the magic bytes), with image decoding on and small limits so that no input can make it
// allocate much. External files resolve against an empty directory.
// Properties: no crash, hang or sanitizer report; a loaded scene keeps every promise of scene.hpp
// (valid indices and material references, one unit normal per position, finite positions, image sizes,
// counts that add up, limits respected, valid lights; animations sampled at any time without trouble); a failure
// always carries an error message.
#include "scene/scene.hpp"
#include "fuzz_support.hpp"

#include <unistd.h>

#include <cmath>
#include <limits>
#include <filesystem>
#include <string>

namespace {

namespace fs = std::filesystem;

// An empty directory for the loader's base_dir, removed at exit.
struct EmptyDir {
  std::string path;
  EmptyDir() {
    const fs::path p = fs::temp_directory_path() / ("dhr-fuzz-scene-" + std::to_string(::getpid()));
    fs::create_directories(p);
    path = p.string();
  }
  ~EmptyDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  EmptyDir(const EmptyDir&) = delete;
  EmptyDir& operator=(const EmptyDir&) = delete;
};

const std::string& empty_dir() {
  static const EmptyDir dir;
  return dir.path;
}

dhr::SceneLoadOptions fuzz_options() {
  dhr::SceneLoadOptions o;
  o.max_file_bytes = 1u << 20;
  o.max_triangles = 100'000;
  o.max_vertices = 300'000;
  o.max_image_dimension = 256;
  o.max_image_bytes = 1u << 20;
  o.decode_images = true;
  o.default_lights_when_none = true;
  return o;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void check_scene(const dhr::Scene& scene, const dhr::SceneLoadOptions& o) {
  uint64_t triangles = 0, vertices = 0, image_bytes = 0;
  for (const dhr::SceneImage& image : scene.images) {
    DHR_FUZZ_CHECK(image.width >= 1 && image.height >= 1);
    DHR_FUZZ_CHECK(image.width <= o.max_image_dimension && image.height <= o.max_image_dimension);
    DHR_FUZZ_CHECK(image.rgba8.size() == size_t{image.width} * image.height * 4);
    image_bytes += image.rgba8.size();
  }
  DHR_FUZZ_CHECK(image_bytes <= o.max_image_bytes);
  for (const dhr::SceneMaterial& m : scene.materials)
    DHR_FUZZ_CHECK(m.base_color_image >= -1 && m.base_color_image < static_cast<int32_t>(scene.images.size()));
  for (const dhr::SceneMesh& mesh : scene.meshes) {
    DHR_FUZZ_CHECK(mesh.material < scene.materials.size());
    DHR_FUZZ_CHECK(mesh.normals.size() == mesh.positions.size());
    DHR_FUZZ_CHECK(mesh.texcoords.empty() || mesh.texcoords.size() == mesh.positions.size());
    DHR_FUZZ_CHECK(mesh.indices.size() % 3 == 0);
    for (uint32_t i : mesh.indices) DHR_FUZZ_CHECK_MSG(i < mesh.positions.size(), "index out of range");
    for (const glm::vec3& p : mesh.positions) DHR_FUZZ_CHECK_MSG(finite(p), "non-finite position");
    for (const glm::vec3& n : mesh.normals) {
      DHR_FUZZ_CHECK_MSG(finite(n), "non-finite normal");
      const float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
      DHR_FUZZ_CHECK_MSG(std::fabs(len - 1.0f) < 1e-3f, "normal not unit length");
    }
    triangles += mesh.triangle_count();
    vertices += mesh.positions.size();
  }
  DHR_FUZZ_CHECK(triangles == scene.triangle_count && vertices == scene.vertex_count);
  DHR_FUZZ_CHECK(triangles <= o.max_triangles && vertices <= o.max_vertices);
  DHR_FUZZ_CHECK(scene.lights.size() <= dhr::kMaxSceneLights);
  for (const dhr::SceneLight& light : scene.lights) {
    // Default rigs included, at any finite coordinates (make_default_light_rig works in double and clamps).
    const auto problem = dhr::validate_light(light);
    DHR_FUZZ_CHECK_MSG(!problem, problem ? problem->c_str() : "");
  }
  DHR_FUZZ_CHECK(scene.warnings.size() <= 65);
  (void)dhr::scene_summary(scene);
  // Animations: sampling at any time (ordinary, past the loop, negative, non-finite) is defined and keeps each
  // light what it is; a clip's local time lies within its duration.
  if (scene.animation.empty()) return;
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const double t : {0.0, 0.37, 1e9, -1.0, nan, inf}) {
    for (const dhr::AnimationClip& clip : scene.animation.clips) {
      const double local = dhr::animation_local_time(t, clip.duration);
      DHR_FUZZ_CHECK(local >= 0.0 && local <= clip.duration);
    }
    for (const dhr::SceneMesh& mesh : scene.meshes) (void)dhr::mesh_motion_at(scene, mesh, t);
    for (const dhr::SceneLight& light : scene.lights) {
      const dhr::SceneLight moved = dhr::light_at(scene, light, t);
      DHR_FUZZ_CHECK(moved.type == light.type && moved.node == light.node);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const dhr::SceneLoadOptions options = fuzz_options();
  const dhr::SceneLoadResult result = dhr::load_scene_from_memory(data, size, empty_dir(), "fuzz-input", options);
  if (result) {
    check_scene(*result.scene, options);
  } else {
    DHR_FUZZ_CHECK_MSG(!result.error.empty(), "failure without an error message");
  }
  return 0;
}
