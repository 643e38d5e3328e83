// Internal to the glTF JSON validator (shared/scene/src/scene_validate*.cpp only): the validator class, whose
// checks are split by what they look at: container, buffers and accessors (scene_validate.cpp); images,
// materials, meshes and lights (scene_validate_materials.cpp); nodes, the hierarchy, scenes and animations
// (scene_validate_nodes.cpp). The public entry point is scene_internal.hpp's validate_gltf_json.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "scene_internal.hpp"
#include "scene_json_check.hpp"

namespace dhr::scene_detail {

class GltfValidator : public JsonCheck {
 public:
  GltfValidator(const Json& root, const ContainerInfo& info, WarningSink& warnings)
      : root_(root), info_(info), warnings_(warnings) {}

  // The first problem found, phrased for a user; std::nullopt when the JSON is usable.
  std::optional<std::string> run();

 private:
  // scene_validate.cpp
  bool check_asset();
  bool check_extensions();
  bool collect_arrays();
  bool check_buffers();
  bool check_buffer_views();
  bool check_view_range(const std::string& path, std::int64_t view, std::uint64_t offset, std::uint64_t count,
                        std::uint64_t stride, std::uint64_t elem);
  bool check_accessors();
  bool check_sparse(const Json& s, const std::string& path, std::uint64_t accessor_count, std::uint64_t elem);
  // scene_validate_materials.cpp
  bool check_images_textures_samplers();
  bool check_texture_info(const Json& o, const char* k, const std::string& path);
  bool check_materials();
  bool check_meshes();
  bool check_lights();
  // scene_validate_nodes.cpp
  bool check_nodes();
  bool check_hierarchy();  // the hierarchy must be a forest
  bool check_scenes();
  bool check_animations();  // structure and references only; the loader checks the data (scene_animation_load.cpp)

  const Json& root_;
  const ContainerInfo& info_;
  WarningSink& warnings_;
  std::vector<const Json*> buffers_, views_, accessors_, images_, samplers_, textures_, materials_, meshes_, nodes_,
      scenes_, cameras_, skins_, animations_;
  std::vector<std::uint64_t> buffer_bytes_;
  std::vector<std::uint64_t> view_bytes_;
  std::size_t light_count_ = 0;
};

}  // namespace dhr::scene_detail
