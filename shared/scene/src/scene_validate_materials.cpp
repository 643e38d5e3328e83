// glTF JSON validation (see scene_validate.cpp): images, textures, samplers, materials, meshes and lights.
#include <string>
#include <vector>

#include "scene_validator.hpp"

namespace dhr::scene_detail {

bool GltfValidator::check_images_textures_samplers() {
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

bool GltfValidator::check_texture_info(const Json& o, const char* k, const std::string& path) {
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

bool GltfValidator::check_materials() {
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

bool GltfValidator::check_meshes() {
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

bool GltfValidator::check_lights() {
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

}  // namespace dhr::scene_detail
