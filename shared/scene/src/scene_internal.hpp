// Internals of the scene loader, shared by the scene_*.cpp files only (never include from outside
// shared/scene/src/scene_*.cpp). tinygltf and nlohmann appear here as forward declarations.
#pragma once
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace tinygltf {
class Model;
class Value;
struct Image;
struct Primitive;
}  // namespace tinygltf

namespace dhr::scene_detail {

// Collects warnings, keeping the first `cap`; take() appends how many were cut.
class WarningSink {
 public:
  explicit WarningSink(std::size_t cap = 64) : cap_(cap) {}
  void add(std::string message);
  void add_lines(const std::string& text);  // one warning per non-empty line (tinygltf's format)
  std::vector<std::string> take();

 private:
  std::size_t cap_;
  std::size_t dropped_ = 0;
  std::vector<std::string> messages_;
};

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

// What the container (GLB or plain JSON) provides besides the JSON.
struct ContainerInfo {
  bool is_glb = false;
  bool has_bin_chunk = false;
  std::uint64_t bin_chunk_bytes = 0;
};

// Checks JSON types, ranges, references, buffer/view/accessor bounds (against the declared byteLengths),
// required extensions, and that the node hierarchy is a forest (no cycles, one parent at most).
// Returns the first problem found, phrased for a user ("meshes[0].primitives: expected an array...").
std::optional<std::string> validate_gltf_json(const nlohmann::json& root, const ContainerInfo& info,
                                              WarningSink& warnings);

// Extensions this loader implements, or that only change shading terms the Lambertian client does not evaluate
// (KHR_materials_*): a file may require them; any other used extension is ignored with a warning naming it.
bool extension_implemented(const std::string& name);

// Image indices used as a base-colour texture by any material (only those get decoded).
std::vector<bool> base_color_image_mask(const nlohmann::json& root);

// User data of decode_image_callback (tinygltf's image loader hook).
struct ImageDecodeContext {
  const SceneLoadOptions* options = nullptr;
  std::vector<bool> wanted;           // by glTF image index
  std::vector<std::string> failures;  // by glTF image index: why it has no pixels ("" = fine)
  std::uint64_t decoded_bytes = 0;
};

// Decodes only wanted images, after checking the header's dimensions against the limits. Never fails
// the load: problems are recorded in ImageDecodeContext::failures and the material falls back.
bool decode_image_callback(tinygltf::Image* image, int image_index, std::string* err, std::string* warn, int req_width,
                           int req_height, const unsigned char* bytes, int size, void* user_data);

// tinygltf's decoded image (8 or 16 bit, 1-4 channels) -> RGBA8. False with a reason when unusable.
bool convert_to_rgba8(const tinygltf::Image& image, SceneImage* out, std::string* out_reason);

// Accessor reading with full bounds checks against the real buffer data.
// Reads `components` values per element as float (normalized integers mapped as glTF defines).
bool read_accessor_floats(const tinygltf::Model& model, int accessor, int components, std::vector<float>* out,
                          std::string* out_error);
bool read_accessor_indices(const tinygltf::Model& model, int accessor, std::vector<std::uint32_t>* out,
                           std::string* out_error);

// Remaining budget of the load (SceneLoadOptions limits).
struct Budget {
  std::uint64_t triangles_left = 0;
  std::uint64_t vertices_left = 0;
};

// How one primitive instance is converted.
struct PrimitiveContext {
  int mesh = 0;
  int primitive = 0;
  std::uint32_t node = 0;
  std::uint32_t geometry = 0;
  std::uint32_t material = 0;  // scene material index
  glm::dmat4 T_world_local{1.0};
  int texcoord_set = -1;           // TEXCOORD_<n> to read; -1: none
  bool texcoord_required = false;  // the material samples a texture with it
  UvTransform uv_transform;
  std::string name;
  bool first_instance = true;  // warn and count file problems once per geometry, not per instance
};

// Converts one triangle-producing primitive (modes 4, 5, 6). Returns false with an error for bad data.
bool convert_primitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive, const PrimitiveContext& ctx,
                       Budget& budget, SceneStats& stats, WarningSink& warnings, SceneMesh* out,
                       std::string* out_error);

struct LightJson;  // below

// The walk's record of one glTF node of the loaded scene (scene_build.cpp), for the animation loader.
struct NodeRest {
  bool in_scene = false;
  std::uint32_t parent = kNoSceneNode;  // glTF index; kNoSceneNode for a scene root
  glm::dmat4 local{1.0};                // as composed by the walk (matrix or T * R * S)
  glm::dmat4 world{1.0};
};

// scene_animation_load.cpp: reads and checks model.animations into `out` (refusing bad data with an error naming
// the animation, channel and problem). `nodes` is indexed by glTF node; `walk_order` lists the scene's nodes,
// parents before children.
bool load_animations(const tinygltf::Model& model, const std::vector<NodeRest>& nodes,
                     const std::vector<std::uint32_t>& walk_order, const SceneLoadOptions& options,
                     WarningSink& warnings, SceneAnimation* out, std::string* out_error);

// Walks the chosen scene and fills `out` (meshes, materials, images, lights, bounds, counts).
bool build_scene(const tinygltf::Model& model, const SceneLoadOptions& options, const ImageDecodeContext& images,
                 const LightJson& light_json, WarningSink& warnings, Scene* out, std::string* out_error);

// scene_gltf_lights.cpp: lights from glTF.
// The raw JSON of light values tinygltf would lose (it drops null members, and JSON writers turn NaN into null):
// the root's extensions.EXT_lights_area and each KHR_lights_punctual light's extras, as JSON text ("" = absent).
struct LightJson {
  std::string area;                 // extensions.EXT_lights_area
  std::vector<std::string> extras;  // by KHR_lights_punctual light index
};
LightJson extract_light_json(const nlohmann::json& root);

// The extent of a KHR_lights_punctual light (extras.radius for point/spot, extras.angle for directional); 0 = none.
struct PunctualExtent {
  float radius = 0.0f;
  float angle = 0.0f;
};
// One per model.lights entry, read once so that a bad value is warned about once (and ignored).
std::vector<PunctualExtent> read_punctual_extents(const tinygltf::Model& model, const LightJson& json,
                                                  WarningSink& warnings);
// KHR_lights_punctual light `index` placed by the node's world transform, with its extent.
SceneLight light_from_gltf(const tinygltf::Model& model, int index, const glm::dmat4& T_world_node,
                           const PunctualExtent& extent);

// One entry of the root's EXT_lights_area.lights, in file units (the node's scale applies at placement).
struct AreaLightDef {
  bool usable = false;  // false: a value was unusable (already warned about); nodes referring to it get no light
  SceneLight::Type type = SceneLight::Type::kRect;
  std::string name;
  glm::vec3 color{1.0f};
  double nits = 0.0;  // luminance of the surface (cd/m^2)
  double size = 1.0;  // rect: height; disk: diameter
  double aspect = 1.0;  // rect: width / height
};
std::vector<AreaLightDef> read_area_lights(const LightJson& json, WarningSink& warnings);
// The area light that node `node`'s EXT_lights_area extension (`node_ext`) refers to, placed by its world
// transform; nullopt, with a warning, for a missing index, an unusable definition or an unusable world size.
std::optional<SceneLight> area_light_from_gltf(const std::vector<AreaLightDef>& defs, const tinygltf::Value& node_ext,
                                               int node, const glm::dmat4& T_world_node, WarningSink& warnings);

}  // namespace dhr::scene_detail
