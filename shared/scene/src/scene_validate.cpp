// Structural validation of the glTF JSON before tinygltf sees it: tinygltf 2.7 skips wrongly typed
// values silently and indexes buffers without bounds checks in places (images from buffer views), so
// everything the loader relies on is checked here first, with messages that name the JSON path.
// This file: the order of the checks, the container, buffers, buffer views and accessors.
#include <algorithm>
#include <string>
#include <vector>

#include "scene_validator.hpp"

namespace dhr::scene_detail {
namespace {

std::uint64_t component_bytes(std::uint64_t component_type) {
  switch (component_type) {
    case 5120:
    case 5121:
      return 1;
    case 5122:
    case 5123:
      return 2;
    case 5125:
    case 5126:
      return 4;
    default:
      return 0;
  }
}

// Element size including the column padding glTF requires for small matrix components.
std::uint64_t element_bytes(const std::string& type, std::uint64_t comp) {
  if (type == "SCALAR") return comp;
  if (type == "VEC2") return 2 * comp;
  if (type == "VEC3") return 3 * comp;
  if (type == "VEC4") return 4 * comp;
  if (type == "MAT2") return comp == 1 ? 8 : 4 * comp;
  if (type == "MAT3") return comp == 1 ? 12 : (comp == 2 ? 24 : 9 * comp);
  if (type == "MAT4") return 16 * comp;
  return 0;
}

}  // namespace

bool extension_implemented(const std::string& name) {
  return name == "KHR_lights_punctual" || name == "EXT_lights_area" || name == "KHR_texture_transform" ||
         name == "KHR_mesh_quantization" || name.rfind("KHR_materials_", 0) == 0;
}

std::optional<std::string> GltfValidator::run() {
  if (!root_.is_object()) return std::string("the top level is ") + kind_name(root_) + ", not a JSON object";
  check_asset() && check_extensions() && collect_arrays() && check_buffers() && check_buffer_views() &&
      check_accessors() && check_images_textures_samplers() && check_materials() && check_meshes() &&
      check_lights() && check_nodes() && check_hierarchy() && check_scenes() && check_animations();
  if (error_.empty()) return std::nullopt;
  return error_;
}

bool GltfValidator::check_asset() {
  const Json* asset = member(root_, "asset", "", Json::value_t::object, true);
  if (!asset) return false;
  const Json* version = member(*asset, "version", "asset", Json::value_t::string, true);
  if (!version) return false;
  const std::string v = version->get<std::string>();
  if (v.rfind("2.", 0) != 0) return fail("asset.version", "glTF version \"" + v + "\" is not supported (need 2.x)");
  return true;
}

bool GltfValidator::check_extensions() {
  for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
    const Json* arr = member(root_, list, "", Json::value_t::array);
    if (!arr) {
      if (!error_.empty()) return false;
      continue;
    }
    for (std::size_t i = 0; i < arr->size(); ++i) {
      if (!(*arr)[i].is_string())
        return fail(at(list, i), std::string("expected a string, got ") + kind_name((*arr)[i]));
    }
  }
  if (auto it = root_.find("extensionsRequired"); it != root_.end()) {
    for (const Json& e : *it) {
      const std::string name = e.get<std::string>();
      if (name == "KHR_draco_mesh_compression") {
        return fail("extensionsRequired",
                    "KHR_draco_mesh_compression (Draco-compressed meshes) is not supported; "
                    "export the scene without Draco compression");
      }
      if (!extension_implemented(name)) {
        return fail("extensionsRequired", "required extension " + name + " is not supported");
      }
    }
  }
  return common(root_, "");
}

bool GltfValidator::collect_arrays() {
  return array_of_objects(root_, "buffers", "", &buffers_) && array_of_objects(root_, "bufferViews", "", &views_) &&
         array_of_objects(root_, "accessors", "", &accessors_) && array_of_objects(root_, "images", "", &images_) &&
         array_of_objects(root_, "samplers", "", &samplers_) && array_of_objects(root_, "textures", "", &textures_) &&
         array_of_objects(root_, "materials", "", &materials_) && array_of_objects(root_, "meshes", "", &meshes_) &&
         array_of_objects(root_, "nodes", "", &nodes_) && array_of_objects(root_, "scenes", "", &scenes_) &&
         array_of_objects(root_, "cameras", "", &cameras_) && array_of_objects(root_, "skins", "", &skins_) &&
         array_of_objects(root_, "animations", "", &animations_);
}

bool GltfValidator::check_buffers() {
  buffer_bytes_.assign(buffers_.size(), 0);
  for (std::size_t i = 0; i < buffers_.size(); ++i) {
    const Json& b = *buffers_[i];
    const std::string path = at("buffers", i);
    if (!uint_member(b, "byteLength", path, &buffer_bytes_[i], true, 1)) return false;
    const Json* uri = member(b, "uri", path, Json::value_t::string);
    if (!error_.empty()) return false;
    if (!uri) {
      if (!info_.is_glb || i != 0) return fail(path, "has no uri (only the first buffer of a .glb may omit it)");
      if (!info_.has_bin_chunk) return fail(path, "refers to the .glb BIN chunk, but the file has none");
      if (buffer_bytes_[i] > info_.bin_chunk_bytes) {
        return fail(path, "byteLength " + std::to_string(buffer_bytes_[i]) + " exceeds the BIN chunk (" +
                              std::to_string(info_.bin_chunk_bytes) + " bytes)");
      }
    }
  }
  return true;
}

bool GltfValidator::check_buffer_views() {
  view_bytes_.assign(views_.size(), 0);
  for (std::size_t i = 0; i < views_.size(); ++i) {
    const Json& v = *views_[i];
    const std::string path = at("bufferViews", i);
    std::int64_t buffer = -1;
    std::uint64_t offset = 0;
    std::uint64_t length = 0;
    std::uint64_t stride = 0;
    if (!index_member(v, "buffer", path, buffers_.size(), "buffer", true, &buffer) ||
        !uint_member(v, "byteOffset", path, &offset, false) ||
        !uint_member(v, "byteLength", path, &length, true, 1) ||
        !uint_member(v, "byteStride", path, &stride, false, 4, 252)) {
      return false;
    }
    const std::uint64_t size = buffer_bytes_[static_cast<std::size_t>(buffer)];
    if (offset > size || length > size - offset) {
      return fail(path, "range [" + std::to_string(offset) + ", " + std::to_string(offset + length) +
                            ") is past the end of buffer " + std::to_string(buffer) + " (" + std::to_string(size) +
                            " bytes)");
    }
    view_bytes_[i] = length;
  }
  return true;
}

bool GltfValidator::check_view_range(const std::string& path, std::int64_t view, std::uint64_t offset,
                                     std::uint64_t count, std::uint64_t stride, std::uint64_t elem) {
  const std::uint64_t size = view_bytes_[static_cast<std::size_t>(view)];
  // count <= 2^32 keeps the products below 2^64 (stride <= 252, elem <= 64).
  const std::uint64_t end = offset + stride * (count - 1) + elem;
  if (count > (1ull << 32) || end > size) {
    return fail(path, "accessor data (offset " + std::to_string(offset) + ", stride " + std::to_string(stride) +
                          ", count " + std::to_string(count) + ") runs past the end of bufferView " +
                          std::to_string(view) + " (" + std::to_string(size) + " bytes)");
  }
  return true;
}

bool GltfValidator::check_accessors() {
  static const char* const kTypes[] = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"};
  for (std::size_t i = 0; i < accessors_.size(); ++i) {
    const Json& a = *accessors_[i];
    const std::string path = at("accessors", i);
    std::int64_t view = -1;
    std::uint64_t offset = 0;
    std::uint64_t component_type = 0;
    std::uint64_t count = 0;
    if (!index_member(a, "bufferView", path, views_.size(), "bufferView", false, &view) ||
        !uint_member(a, "byteOffset", path, &offset, false) ||
        !uint_member(a, "componentType", path, &component_type, true) ||
        !uint_member(a, "count", path, &count, true, 1)) {
      return false;
    }
    const std::uint64_t comp = component_bytes(component_type);
    if (comp == 0)
      return fail(key(path, "componentType"), "unknown component type " + std::to_string(component_type));
    const Json* type = member(a, "type", path, Json::value_t::string, true);
    if (!type) return false;
    const std::string t = type->get<std::string>();
    if (std::find(std::begin(kTypes), std::end(kTypes), t) == std::end(kTypes)) {
      return fail(key(path, "type"), "unknown accessor type \"" + t + "\"");
    }
    member(a, "normalized", path, Json::value_t::boolean);
    member(a, "min", path, Json::value_t::array);
    member(a, "max", path, Json::value_t::array);
    if (!error_.empty()) return false;
    const std::uint64_t elem = element_bytes(t, comp);
    if (view >= 0) {
      std::uint64_t stride = elem;
      const Json& view_json = *views_[static_cast<std::size_t>(view)];
      if (auto s = view_json.find("byteStride"); s != view_json.end()) as_uint(*s, &stride);
      if (stride < elem) {
        return fail(path, "bufferView " + std::to_string(view) + " byteStride " + std::to_string(stride) +
                              " is smaller than the element size " + std::to_string(elem));
      }
      if (!check_view_range(path, view, offset, count, stride, elem)) return false;
    }
    if (const Json* sparse = member(a, "sparse", path, Json::value_t::object)) {
      if (!check_sparse(*sparse, key(path, "sparse"), count, elem)) return false;
    }
    if (!error_.empty()) return false;
  }
  return true;
}

bool GltfValidator::check_sparse(const Json& s, const std::string& path, std::uint64_t accessor_count,
                                 std::uint64_t elem) {
  std::uint64_t count = 0;
  if (!uint_member(s, "count", path, &count, true, 1, accessor_count)) return false;
  const Json* indices = member(s, "indices", path, Json::value_t::object, true);
  const Json* values = member(s, "values", path, Json::value_t::object, true);
  if (!indices || !values) return false;
  std::int64_t view = -1;
  std::uint64_t offset = 0;
  std::uint64_t component_type = 0;
  const std::string ipath = key(path, "indices");
  if (!index_member(*indices, "bufferView", ipath, views_.size(), "bufferView", true, &view) ||
      !uint_member(*indices, "byteOffset", ipath, &offset, false) ||
      !uint_member(*indices, "componentType", ipath, &component_type, true)) {
    return false;
  }
  if (component_type != 5121 && component_type != 5123 && component_type != 5125) {
    return fail(key(ipath, "componentType"),
                "must be an unsigned integer type, got " + std::to_string(component_type));
  }
  const std::uint64_t comp = component_bytes(component_type);
  if (!check_view_range(ipath, view, offset, count, comp, comp)) return false;
  const std::string vpath = key(path, "values");
  offset = 0;
  if (!index_member(*values, "bufferView", vpath, views_.size(), "bufferView", true, &view) ||
      !uint_member(*values, "byteOffset", vpath, &offset, false)) {
    return false;
  }
  return check_view_range(vpath, view, offset, count, elem, elem);
}

std::optional<std::string> validate_gltf_json(const nlohmann::json& root, const ContainerInfo& info,
                                              WarningSink& warnings) {
  return GltfValidator(root, info, warnings).run();
}

std::vector<bool> base_color_image_mask(const nlohmann::json& root) {
  // Only called after validation, so every index below is in range.
  std::vector<bool> mask(root.contains("images") ? root["images"].size() : 0, false);
  if (!root.contains("materials") || !root.contains("textures")) return mask;
  const Json& textures = root["textures"];
  for (const Json& m : root["materials"]) {
    auto pbr = m.find("pbrMetallicRoughness");
    if (pbr == m.end()) continue;
    auto info = pbr->find("baseColorTexture");
    if (info == pbr->end()) continue;
    const Json& texture = textures[(*info)["index"].get<std::size_t>()];
    if (auto source = texture.find("source"); source != texture.end()) mask[source->get<std::size_t>()] = true;
  }
  return mask;
}

}  // namespace dhr::scene_detail
