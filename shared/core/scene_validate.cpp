// Structural validation of the glTF JSON before tinygltf sees it: tinygltf 2.7 skips wrongly typed
// values silently and indexes buffers without bounds checks in places (images from buffer views), so
// everything the loader relies on is checked here first, with messages that name the JSON path.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/scene_internal.hpp"
#include "core/scene_json_check.hpp"

namespace dhr::scene_detail {
namespace {

// Extensions that only change shading (or that this loader implements) may be required.
bool required_extension_supported(const std::string& name) {
  return name == "KHR_lights_punctual" || name == "KHR_texture_transform" || name == "KHR_mesh_quantization" ||
         name.rfind("KHR_materials_", 0) == 0;
}

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

class Validator : public JsonCheck {
 public:
  Validator(const Json& root, const ContainerInfo& info, WarningSink& warnings)
      : root_(root), info_(info), warnings_(warnings) {}

  std::optional<std::string> run() {
    if (!root_.is_object()) return std::string("the top level is ") + kind_name(root_) + ", not a JSON object";
    check_asset() && check_extensions() && collect_arrays() && check_buffers() && check_buffer_views() &&
        check_accessors() && check_images_textures_samplers() && check_materials() && check_meshes() &&
        check_lights() && check_nodes() && check_hierarchy() && check_scenes();
    if (error_.empty()) return std::nullopt;
    return error_;
  }

 private:
  bool check_asset() {
    const Json* asset = member(root_, "asset", "", Json::value_t::object, true);
    if (!asset) return false;
    const Json* version = member(*asset, "version", "asset", Json::value_t::string, true);
    if (!version) return false;
    const std::string v = version->get<std::string>();
    if (v.rfind("2.", 0) != 0) return fail("asset.version", "glTF version \"" + v + "\" is not supported (need 2.x)");
    return true;
  }

  bool check_extensions() {
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
        if (!required_extension_supported(name)) {
          return fail("extensionsRequired", "required extension " + name + " is not supported");
        }
      }
    }
    return common(root_, "");
  }

  bool collect_arrays() {
    return array_of_objects(root_, "buffers", "", &buffers_) && array_of_objects(root_, "bufferViews", "", &views_) &&
           array_of_objects(root_, "accessors", "", &accessors_) && array_of_objects(root_, "images", "", &images_) &&
           array_of_objects(root_, "samplers", "", &samplers_) && array_of_objects(root_, "textures", "", &textures_) &&
           array_of_objects(root_, "materials", "", &materials_) && array_of_objects(root_, "meshes", "", &meshes_) &&
           array_of_objects(root_, "nodes", "", &nodes_) && array_of_objects(root_, "scenes", "", &scenes_) &&
           array_of_objects(root_, "cameras", "", &cameras_) && array_of_objects(root_, "skins", "", &skins_) &&
           array_of_objects(root_, "animations", "", &animations_);
  }

  bool check_buffers() {
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

  bool check_buffer_views() {
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

  bool check_view_range(const std::string& path, std::int64_t view, std::uint64_t offset, std::uint64_t count,
                        std::uint64_t stride, std::uint64_t elem) {
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

  bool check_accessors() {
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

  bool check_sparse(const Json& s, const std::string& path, std::uint64_t accessor_count, std::uint64_t elem) {
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

  bool check_images_textures_samplers() {
    for (std::size_t i = 0; i < images_.size(); ++i) {
      const Json& im = *images_[i];
      const std::string path = at("images", i);
      const bool has_uri = member(im, "uri", path, Json::value_t::string) != nullptr;
      if (!index_member(im, "bufferView", path, views_.size(), "bufferView", false)) return false;
      member(im, "mimeType", path, Json::value_t::string);
      if (!error_.empty()) return false;
      const bool has_view = im.contains("bufferView");
      if (has_uri == has_view) return fail(path, "needs exactly one of \"uri\" and \"bufferView\"");
    }
    for (std::size_t i = 0; i < samplers_.size(); ++i) {
      const std::string path = at("samplers", i);
      std::uint64_t v = 0;
      for (const char* k : {"magFilter", "minFilter", "wrapS", "wrapT"}) {
        if (!uint_member(*samplers_[i], k, path, &v, false)) return false;
      }
    }
    for (std::size_t i = 0; i < textures_.size(); ++i) {
      const std::string path = at("textures", i);
      if (!index_member(*textures_[i], "source", path, images_.size(), "image", false) ||
          !index_member(*textures_[i], "sampler", path, samplers_.size(), "sampler", false)) {
        return false;
      }
    }
    return true;
  }

  bool check_texture_info(const Json& o, const char* k, const std::string& path) {
    const Json* info = member(o, k, path, Json::value_t::object);
    if (!info) return error_.empty();
    const std::string p = key(path, k);
    std::uint64_t tex_coord = 0;
    if (!common(*info, p) || !number_member(*info, "scale", p, -1.0e30, 1.0e30) ||
        !number_member(*info, "strength", p, -1.0e30, 1.0e30) ||
        !index_member(*info, "index", p, textures_.size(), "texture", true) ||
        !uint_member(*info, "texCoord", p, &tex_coord, false, 0, 31)) {
      return false;
    }
    if (auto ext = info->find("extensions"); ext != info->end()) {
      if (auto tt = ext->find("KHR_texture_transform"); tt != ext->end()) {
        const std::string tp = p + ".extensions.KHR_texture_transform";
        if (!numbers_member(*tt, "offset", tp, 2) || !numbers_member(*tt, "scale", tp, 2) ||
            !number_member(*tt, "rotation", tp, -1.0e6, 1.0e6) ||
            !uint_member(*tt, "texCoord", tp, &tex_coord, false, 0, 31)) {
          return false;
        }
      }
    }
    return true;
  }

  bool check_materials() {
    for (std::size_t i = 0; i < materials_.size(); ++i) {
      const Json& m = *materials_[i];
      const std::string path = at("materials", i);
      if (const Json* pbr = member(m, "pbrMetallicRoughness", path, Json::value_t::object)) {
        const std::string p = key(path, "pbrMetallicRoughness");
        if (!common(*pbr, p) || !numbers_member(*pbr, "baseColorFactor", p, 4) ||
            !check_texture_info(*pbr, "baseColorTexture", p) ||
            !check_texture_info(*pbr, "metallicRoughnessTexture", p) ||
            !number_member(*pbr, "metallicFactor", p, 0.0, 1.0) ||
            !number_member(*pbr, "roughnessFactor", p, 0.0, 1.0)) {
          return false;
        }
      }
      if (!error_.empty() || !check_texture_info(m, "normalTexture", path) ||
          !check_texture_info(m, "occlusionTexture", path) || !check_texture_info(m, "emissiveTexture", path) ||
          !numbers_member(m, "emissiveFactor", path, 3) || !number_member(m, "alphaCutoff", path, 0.0, 1.0e30)) {
        return false;
      }
      member(m, "doubleSided", path, Json::value_t::boolean);
      if (const Json* mode = member(m, "alphaMode", path, Json::value_t::string)) {
        const std::string s = mode->get<std::string>();
        if (s != "OPAQUE" && s != "MASK" && s != "BLEND")
          return fail(key(path, "alphaMode"), "unknown mode \"" + s + "\"");
      }
      if (!error_.empty()) return false;
    }
    return true;
  }

  bool check_meshes() {
    for (std::size_t i = 0; i < meshes_.size(); ++i) {
      const std::string path = at("meshes", i);
      const Json* prims = member(*meshes_[i], "primitives", path, Json::value_t::array, true);
      if (!prims) return false;
      if (prims->empty()) return fail(key(path, "primitives"), "is empty");
      for (std::size_t j = 0; j < prims->size(); ++j) {
        const Json& p = (*prims)[j];
        const std::string pp = at(key(path, "primitives"), j);
        if (!p.is_object()) return fail(pp, std::string("expected an object, got ") + kind_name(p));
        if (!common(p, pp)) return false;
        const Json* attributes = member(p, "attributes", pp, Json::value_t::object, true);
        if (!attributes) return false;
        for (auto it = attributes->begin(); it != attributes->end(); ++it) {
          if (!index_member(*attributes, it.key().c_str(), key(pp, "attributes"), accessors_.size(), "accessor",
                            true)) {
            return false;
          }
        }
        std::uint64_t mode = 4;
        if (!index_member(p, "indices", pp, accessors_.size(), "accessor", false) ||
            !index_member(p, "material", pp, materials_.size(), "material", false) ||
            !uint_member(p, "mode", pp, &mode, false, 0, 6)) {
          return false;
        }
        member(p, "targets", pp, Json::value_t::array);
        if (!error_.empty()) return false;
        if (auto ext = p.find("extensions"); ext != p.end() && ext->contains("KHR_draco_mesh_compression")) {
          warnings_.add(pp +
                        ": ignoring its KHR_draco_mesh_compression data (Draco is not supported); "
                        "using the uncompressed accessors");
        }
      }
    }
    return true;
  }

  bool check_lights() {
    auto ext = root_.find("extensions");
    if (ext == root_.end()) return true;
    auto lp = ext->find("KHR_lights_punctual");
    if (lp == ext->end()) return true;
    const std::string base = "extensions.KHR_lights_punctual";
    std::vector<const Json*> lights;
    if (!array_of_objects(*lp, "lights", base, &lights)) return false;
    light_count_ = lights.size();
    for (std::size_t i = 0; i < lights.size(); ++i) {
      const Json& l = *lights[i];
      const std::string path = at(key(base, "lights"), i);
      const Json* type = member(l, "type", path, Json::value_t::string, true);
      if (!type) return false;
      const std::string t = type->get<std::string>();
      if (t != "point" && t != "spot" && t != "directional")
        return fail(key(path, "type"), "unknown light type \"" + t + "\"");
      double range = 0.0;
      if (!numbers_member(l, "color", path, 3) || !number_member(l, "intensity", path, 0.0, 1.0e30) ||
          !number_member(l, "range", path, 0.0, 1.0e30, &range)) {
        return false;
      }
      if (const Json* spot = member(l, "spot", path, Json::value_t::object)) {
        double inner = 0.0;
        double outer = 0.78539816339744831;
        const std::string sp = key(path, "spot");
        if (!number_member(*spot, "innerConeAngle", sp, 0.0, 1.5707963267948966, &inner) ||
            !number_member(*spot, "outerConeAngle", sp, 0.0, 1.5707963267948966, &outer)) {
          return false;
        }
        if (!(inner < outer)) return fail(sp, "innerConeAngle must be smaller than outerConeAngle");
      }
      if (!error_.empty()) return false;
      if (auto c = l.find("color"); c != l.end()) {
        for (const Json& v : *c) {
          if (v.get<double>() < 0.0) return fail(key(path, "color"), "negative colour component");
        }
      }
    }
    return true;
  }

  bool check_nodes() {
    static const std::pair<const char*, std::size_t> kVectors[] = {
        {"matrix", 16}, {"translation", 3}, {"rotation", 4}, {"scale", 3}};
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const Json& n = *nodes_[i];
      const std::string path = at("nodes", i);
      if (!index_member(n, "mesh", path, meshes_.size(), "mesh", false) ||
          !index_member(n, "camera", path, cameras_.size(), "camera", false) ||
          !index_member(n, "skin", path, skins_.size(), "skin", false)) {
        return false;
      }
      for (const auto& [k, count] : kVectors) {
        if (!numbers_member(n, k, path, count)) return false;
      }
      if (n.contains("matrix") && (n.contains("translation") || n.contains("rotation") || n.contains("scale"))) {
        warnings_.add(path + ": has both a matrix and TRS properties; using the matrix");
      }
      if (const Json* children = member(n, "children", path, Json::value_t::array)) {
        for (std::size_t c = 0; c < children->size(); ++c) {
          std::uint64_t child = 0;
          if (!as_uint((*children)[c], &child) || child >= nodes_.size()) {
            return fail(at(key(path, "children"), c), "is not a valid node index (" + (*children)[c].dump() + ")");
          }
        }
      }
      if (auto ext = n.find("extensions"); ext != n.end()) {
        if (auto lp = ext->find("KHR_lights_punctual"); lp != ext->end()) {
          if (!index_member(*lp, "light", path + ".extensions.KHR_lights_punctual", light_count_, "light", true)) {
            return false;
          }
        }
      }
      if (!error_.empty()) return false;
    }
    return true;
  }

  // The hierarchy must be a forest: each node has at most one parent and following parents never loops.
  bool check_hierarchy() {
    constexpr std::size_t kNone = ~std::size_t{0};
    std::vector<std::size_t> parent(nodes_.size(), kNone);
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      auto children = nodes_[i]->find("children");
      if (children == nodes_[i]->end()) continue;
      for (const Json& c : *children) {
        const std::size_t child = c.get<std::size_t>();
        if (child == i) return fail(at("nodes", i), "node cycle: node " + std::to_string(i) + " is its own child");
        if (parent[child] != kNone && parent[child] != i) {
          // A node with two parents may still be a cycle (0 -> 1 -> 0 gives node 0 parents 1 and none).
          return fail(at("nodes", child), "is a child of both node " + std::to_string(parent[child]) + " and node " +
                                              std::to_string(i) + " (the node hierarchy must be a tree)");
        }
        parent[child] = i;
      }
    }
    // 0 = unknown, 1 = on the current upward walk, 2 = reaches a root.
    std::vector<std::uint8_t> state(nodes_.size(), 0);
    std::vector<std::size_t> walk;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      walk.clear();
      std::size_t n = i;
      while (n != kNone && state[n] == 0) {
        state[n] = 1;
        walk.push_back(n);
        n = parent[n];
      }
      if (n != kNone && state[n] == 1) {
        // walk runs child -> parent; print the loop parent -> child, starting and ending at one node.
        const auto start = std::find(walk.begin(), walk.end(), n);
        std::string cycle = "node cycle: ";
        for (auto it = walk.end(); it != start;) {
          --it;
          cycle += std::to_string(*it) + " -> ";
        }
        cycle += std::to_string(walk.back());
        return fail("nodes", cycle);
      }
      for (std::size_t w : walk) state[w] = 2;
    }
    return true;
  }

  bool check_scenes() {
    for (std::size_t i = 0; i < scenes_.size(); ++i) {
      const std::string path = at("scenes", i);
      if (const Json* roots = member(*scenes_[i], "nodes", path, Json::value_t::array)) {
        for (std::size_t r = 0; r < roots->size(); ++r) {
          std::uint64_t node = 0;
          if (!as_uint((*roots)[r], &node) || node >= nodes_.size()) {
            return fail(at(key(path, "nodes"), r), "is not a valid node index (" + (*roots)[r].dump() + ")");
          }
        }
      }
      if (!error_.empty()) return false;
    }
    if (scenes_.empty()) return fail("scenes", "the file has no scenes, so there is nothing to show");
    std::int64_t scene = 0;
    if (!index_member(root_, "scene", "", scenes_.size(), "scene", false, &scene)) return false;
    const Json& chosen = *scenes_[static_cast<std::size_t>(scene)];
    if (!chosen.contains("nodes") || chosen["nodes"].empty()) {
      return fail(at("scenes", static_cast<std::size_t>(scene)), "the scene to show has no nodes");
    }
    return true;
  }

  const Json& root_;
  const ContainerInfo& info_;
  WarningSink& warnings_;
  std::vector<const Json*> buffers_, views_, accessors_, images_, samplers_, textures_, materials_, meshes_, nodes_,
      scenes_, cameras_, skins_, animations_;
  std::vector<std::uint64_t> buffer_bytes_;
  std::vector<std::uint64_t> view_bytes_;
  std::size_t light_count_ = 0;
};

}  // namespace

std::optional<std::string> validate_gltf_json(const nlohmann::json& root, const ContainerInfo& info,
                                              WarningSink& warnings) {
  return Validator(root, info, warnings).run();
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
