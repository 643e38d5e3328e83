// Scenes: glTF 2.0 (.gltf / .glb) loaded into a flattened, world-space triangle scene with materials,
// base-colour images (RGBA8) and punctual lights. Plain structs only: tinygltf stays inside the .cpp
// files. Units are metres, +Y up (glTF). See docs/scenes.md for the supported features and limits.
#pragma once
#include <cstddef>
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene_animation.hpp"

namespace dhr {

// The shadow mask carries one bit per light; more lights than this cannot be traced.
inline constexpr std::uint32_t kMaxSceneLights = 256;  // beyond 32 they share light slots (light_slots.hpp)
// The project's own scene, relative to the repository root (used when no scene is given).
inline constexpr const char* kDefaultScenePath = "assets/scenes/default_room.gltf";
// Limits of a light's extent: larger values are refused (a file's light loses its extent or is skipped, with a
// warning; validate_light rejects them). 100 m is far beyond any real lamp; 0.5 rad (29 degrees) is 50 suns.
inline constexpr float kMaxLightExtent = 100.0f;  // metres: radius, width, height
inline constexpr float kMaxLightAngle = 0.5f;     // radians: a directional light's angular diameter

struct SceneBounds {
  glm::vec3 min{std::numeric_limits<float>::max()};
  glm::vec3 max{std::numeric_limits<float>::lowest()};

  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void extend(const glm::vec3& p);
  void extend(const SceneBounds& other);
  glm::vec3 center() const;  // (0,0,0) when empty
  glm::vec3 size() const;    // (0,0,0) when empty
  float diagonal() const;    // 0 when empty
};

// A decoded base-colour image: width * height * 4 bytes, rows top to bottom, sRGB-encoded RGBA8.
struct SceneImage {
  std::string name;  // the glTF image name, else its uri (data URIs shortened), else "image<N>"
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> rgba8;
};

enum class TextureWrap : std::uint8_t { kRepeat, kClampToEdge, kMirroredRepeat };
enum class AlphaMode : std::uint8_t { kOpaque, kMask, kBlend };

// KHR_texture_transform of the base-colour texture: uv' = offset + R(rotation) * (scale * uv).
struct UvTransform {
  glm::vec2 offset{0.0f};
  float rotation = 0.0f;  // radians, counter-clockwise in UV space as the extension defines it
  glm::vec2 scale{1.0f};
  bool present = false;  // the material had the extension
  glm::vec2 apply(const glm::vec2& uv) const;
};

struct SceneMaterial {
  std::string name;
  glm::vec4 base_color_factor{1.0f};   // linear RGBA, multiplies the image
  std::int32_t base_color_image = -1;  // index into Scene::images; -1: none (missing image -> -1, warned)
  TextureWrap wrap_s = TextureWrap::kRepeat;
  TextureWrap wrap_t = TextureWrap::kRepeat;
  // Informational: the loader already applied it to SceneMesh::texcoords.
  UvTransform base_color_uv_transform;
  bool double_sided = false;
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;
};

// One instance of one glTF mesh primitive, as a triangle list in world space.
struct SceneMesh {
  std::string name;            // "<mesh name or mesh<N>>/<primitive index>"
  std::uint32_t material = 0;  // index into Scene::materials (always valid)
  std::uint32_t geometry = 0;  // equal for instances of the same glTF mesh primitive
  std::uint32_t node = 0;      // the glTF node that instances it
  // World transform of that node (double). Instances with the same `geometry` share local-space data:
  // local = inverse(T_world_local) * world, indices identical; enough to build one BLAS per geometry.
  glm::dmat4 T_world_local{1.0};
  std::vector<glm::vec3> positions;    // world space
  std::vector<glm::vec3> normals;      // world space, unit length, one per position
  std::vector<glm::vec2> texcoords;    // empty, or one per position (uv transform applied)
  std::vector<std::uint32_t> indices;  // triangle list, counter-clockwise front faces in world space

  std::size_t triangle_count() const { return indices.size() / 3; }
};

struct SceneLight {
  // kRect, kDisk: EXT_lights_area (one-sided, emitting along `direction`, the node's -Z).
  enum class Type : std::uint8_t { kPoint, kSpot, kDirectional, kRect, kDisk };
  Type type = Type::kPoint;
  std::string name;
  glm::vec3 position{0.0f};                // world space (point, spot)
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // world space, unit: where the light travels (spot, directional)
  glm::vec3 color{1.0f};                   // linear RGB
  // candela (point, spot), lux (directional), or the luminance of the emitting surface in nits (cd/m^2; rect, disk),
  // as glTF and EXT_lights_area define them. An area light's peak intensity (along `direction`) is nits x area.
  float intensity = 1.0f;
  float range = 0.0f;                      // metres; 0 = infinite
  float inner_cone = 0.0f;                 // radians (spot)
  float outer_cone = 0.78539816f;          // radians (spot), > inner_cone, <= pi/2
  bool is_default = false;                 // made by make_default_light_rig, not by the file or the user
  // The light's extent (soft shadows); all 0 for a punctual light (hard shadows).
  float radius = 0.0f;                     // sphere light (point, spot: glTF extras.radius), metres
  float angle = 0.0f;                      // disk sun (directional: glTF extras.angle), angular diameter, radians
  float width = 0.0f;                      // rect: extent along `tangent`; disk: diameter; metres
  float height = 0.0f;                     // rect: extent along `bitangent`; disk: diameter; metres
  glm::vec3 tangent{1.0f, 0.0f, 0.0f};     // rect, disk: world direction of the node's +X (unit)
  glm::vec3 bitangent{0.0f, 1.0f, 0.0f};   // rect, disk: world direction of the node's +Y (unit)
  std::uint32_t node = kNoSceneNode;       // the glTF node that places it (kNoSceneNode: from a spec or the rig)

  bool has_extent() const { return radius > 0.0f || angle > 0.0f || width > 0.0f || height > 0.0f; }
  // Emitting area in m^2: width x height (rect), pi (width/2)^2 (disk), 0 otherwise.
  float area() const;
};

// Counts of what the loader changed or skipped (each also produces a warning when non-zero).
struct SceneStats {
  std::uint32_t point_primitives_skipped = 0;
  std::uint32_t line_primitives_skipped = 0;
  std::uint32_t strips_converted = 0;
  std::uint32_t fans_converted = 0;
  std::uint32_t meshes_with_generated_normals = 0;  // flat normals computed (no NORMAL attribute)
  std::uint64_t normals_renormalized = 0;           // non-unit normals in the file
  std::uint64_t normals_repaired = 0;               // zero / non-finite normals replaced
  std::uint32_t lights_dropped = 0;                 // beyond kMaxSceneLights
};

struct Scene {
  std::string source;  // the file it came from
  std::vector<SceneMesh> meshes;
  std::vector<SceneMaterial> materials;
  std::vector<SceneImage> images;
  std::vector<SceneLight> lights;  // at most kMaxSceneLights
  bool default_lights = false;     // lights came from make_default_light_rig
  SceneBounds bounds;              // of all triangle vertices (world space)
  std::uint64_t triangle_count = 0;
  std::uint64_t vertex_count = 0;
  SceneStats stats;
  SceneAnimation animation;  // empty for a static scene (see scene/scene_animation.hpp)
  std::vector<std::string> warnings;  // human-readable; capped (the last entry says how many were cut)

  // Some light has an extent (SceneLight::has_extent): the scene has soft shadows.
  bool has_soft_lights() const {
    for (const SceneLight& l : lights) {
      if (l.has_extent()) return true;
    }
    return false;
  }
};

// Guards so that an absurd or hostile file cannot exhaust memory. Defaults are generous but bounded.
struct SceneLoadOptions {
  std::uint64_t max_file_bytes = 1ull << 30;   // each file read: .gltf/.glb, each .bin, each image
  std::uint64_t max_triangles = 32'000'000;    // after instancing
  std::uint64_t max_vertices = 64'000'000;     // after instancing (and after flat-normal unwelding)
  std::uint32_t max_image_dimension = 16384;   // width or height of a decoded image
  std::uint64_t max_image_bytes = 1ull << 30;  // all decoded RGBA8 images together
  bool decode_images = true;                   // false: materials keep only their colour factor
  bool default_lights_when_none = true;        // no lights in the file -> make_default_light_rig
  std::uint64_t max_animation_keys = 10'000'000;  // input keys of all animation samplers together
};

struct SceneLoadResult {
  std::optional<Scene> scene;
  std::string error;  // "<file>: <problem>" when there is no scene

  bool ok() const { return scene.has_value(); }
  explicit operator bool() const { return ok(); }
};

// Loads the default scene (or scene 0) of a .gltf or .glb file. Never throws; bad input gives an error.
SceneLoadResult load_scene(const std::string& path, const SceneLoadOptions& options = {});

// Same from memory (.gltf JSON text or .glb bytes); external files resolve against base_dir and
// `name` stands for the file in messages.
SceneLoadResult load_scene_from_memory(const void* data, std::size_t size, const std::string& base_dir,
                                       const std::string& name, const SceneLoadOptions& options = {});

// Three lights derived from the bounding box (documented in docs/scenes.md): a warm key point light
// high and in front, a cooler, dimmer fill point light on the other side, and a directional "sun".
// Every light is flagged is_default. An empty box is treated as a 2 m cube around the origin.
std::vector<SceneLight> make_default_light_rig(const SceneBounds& bounds);

// Light spec strings, for command lines and configs (numbers in metres, linear RGB, glTF units):
//   point:x,y,z:r,g,b:intensity[:range][:radius=R]
//   spot:x,y,z:dx,dy,dz:r,g,b:intensity:inner_deg,outer_deg[:range][:radius=R]
//   dir:dx,dy,dz:r,g,b:intensity[:angle_deg=A]            ("directional" is accepted for "dir")
//   rect:x,y,z:dx,dy,dz:tx,ty,tz:r,g,b:nits:width,height[:range]
//   disk:x,y,z:dx,dy,dz:tx,ty,tz:r,g,b:nits:diameter,diameter[:range]
// The direction is where the light travels; it is normalized. radius= makes a sphere light (metres), angle_deg= a
// sun disk (angular diameter in degrees). rect/disk: t is the tangent (the emitter's +X, along `width`); it is
// made orthogonal to the direction and the bitangent (+Y, along `height`) completes the frame.
std::optional<SceneLight> parse_light_spec(std::string_view spec, std::string* out_error);
// Several specs separated by ';' (empty entries ignored). Fails when any fails or when > kMaxSceneLights.
std::optional<std::vector<SceneLight>> parse_light_specs(std::string_view specs, std::string* out_error);
// The spec string for a light (round-trips through parse_light_spec, up to float printing).
std::string format_light_spec(const SceneLight& light);

// Error message when the light is unusable (non-finite, negative colour or intensity, bad cone...).
std::optional<std::string> validate_light(const SceneLight& light);

// Replaces the scene's lights (e.g. with parsed specs). Error (scene unchanged) when a light is invalid
// or there are more than kMaxSceneLights.
std::optional<std::string> set_scene_lights(Scene& scene, std::vector<SceneLight> lights);

const char* light_type_name(SceneLight::Type type);  // "point", "spot", "dir", "rect", "disk"

// One line describing a light's type and extent for people: "rect 1 x 0.4 m", "point, sphere r 0.06 m",
// "dir, sun disk 0.53 deg", "spot" (punctual).
std::string describe_light_extent(const SceneLight& light);

// One line for logs: triangles, meshes, materials, images, lights, bounds.
std::string scene_summary(const Scene& scene);

}  // namespace dhr
