// Walks the chosen glTF scene (iteratively, so deep hierarchies cannot overflow the stack), composes node
// transforms in double, converts materials and base-colour images, and collects meshes and lights.
#include <tiny_gltf.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <tuple>
#include <utility>

#include "scene_internal.hpp"

namespace dhr::scene_detail {
namespace {

double number(const tinygltf::Value& v, double fallback) { return v.IsNumber() ? v.GetNumberAsDouble() : fallback; }

TextureWrap wrap_mode(int gl) {
  switch (gl) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
      return TextureWrap::kClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
      return TextureWrap::kMirroredRepeat;
    default:
      return TextureWrap::kRepeat;
  }
}

// Node-local transform: the matrix (column-major) if given, else T * R * S.
glm::dmat4 local_transform(const tinygltf::Node& node, WarningSink& warnings, int index) {
  if (node.matrix.size() == 16) {
    glm::dmat4 m(1.0);
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[static_cast<std::size_t>(4 * c + r)];
    }
    return m;
  }
  glm::dmat4 m(1.0);
  if (node.translation.size() == 3) {
    m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  }
  if (node.rotation.size() == 4) {
    glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // glTF: x, y, z, w
    const double len = glm::length(q);
    if (len > 1e-12 && std::isfinite(len)) {
      m = m * glm::mat4_cast(q / len);
    } else {
      warnings.add(format("nodes[%d]: zero rotation quaternion; using no rotation", index));
    }
  }
  if (node.scale.size() == 3) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

// What the loader needs to know about a material beyond SceneMaterial.
struct MaterialTexturing {
  int texcoord_set = -1;  // TEXCOORD_<n> of a usable base-colour texture
  UvTransform transform;
};

class Builder {
 public:
  Builder(const tinygltf::Model& model, const SceneLoadOptions& options, const ImageDecodeContext& images,
          const LightJson& light_json, WarningSink& warnings, Scene* out)
      : model_(model), options_(options), images_(images), light_json_(light_json), warnings_(warnings), out_(out) {
    budget_.triangles_left = options.max_triangles;
    budget_.vertices_left = options.max_vertices;
  }

  bool run(std::string* out_error) {
    if (model_.scenes.empty()) return fail("the file has no scenes, so there is nothing to show", out_error);
    const int scene_index = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    if (static_cast<std::size_t>(scene_index) >= model_.scenes.size()) {
      return fail(format("scene %d does not exist", scene_index), out_error);
    }
    const tinygltf::Scene& scene = model_.scenes[static_cast<std::size_t>(scene_index)];
    if (scene.nodes.empty()) return fail(format("scene %d has no nodes", scene_index), out_error);
    convert_materials();
    punctual_extents_ = read_punctual_extents(model_, light_json_, warnings_);
    area_defs_ = read_area_lights(light_json_, warnings_);
    if (!walk(scene, scene_index, out_error)) return false;
    if (!load_animations(model_, node_rest_, walk_order_, options_, warnings_, &out_->animation, out_error)) {
      return false;
    }
    finish();
    return true;
  }

 private:
  static bool fail(const std::string& message, std::string* out_error) {
    *out_error = message;
    return false;
  }

  // glTF image index -> Scene::images index, converting on first use; -1 when unusable (reason set).
  int scene_image(int gltf_image, std::string* out_reason) {
    if (gltf_image < 0 || static_cast<std::size_t>(gltf_image) >= model_.images.size()) {
      *out_reason = "does not exist";
      return -1;
    }
    auto it = image_map_.find(gltf_image);
    if (it != image_map_.end()) {
      *out_reason = it->second.second;
      return it->second.first;
    }
    const tinygltf::Image& image = model_.images[static_cast<std::size_t>(gltf_image)];
    std::string reason;
    int index = -1;
    if (!options_.decode_images) {
      reason = "was not decoded (decode_images is off)";
    } else if (static_cast<std::size_t>(gltf_image) < images_.failures.size() &&
               !images_.failures[static_cast<std::size_t>(gltf_image)].empty()) {
      reason = images_.failures[static_cast<std::size_t>(gltf_image)];
    } else {
      SceneImage converted;
      if (convert_to_rgba8(image, &converted, &reason)) {
        converted.name = !image.name.empty()                                        ? image.name
                         : (!image.uri.empty() && image.uri.rfind("data:", 0) != 0) ? image.uri
                                                                                    : format("image%d", gltf_image);
        index = static_cast<int>(out_->images.size());
        out_->images.push_back(std::move(converted));
      }
    }
    if (index < 0 && !image.uri.empty() && image.uri.rfind("data:", 0) != 0) {
      reason = "('" + image.uri + "') " + reason;
    }
    image_map_[gltf_image] = {index, reason};
    *out_reason = reason;
    return index;
  }

  void convert_materials() {
    out_->materials.reserve(model_.materials.size() + 1);
    texturing_.resize(model_.materials.size());
    for (std::size_t i = 0; i < model_.materials.size(); ++i) {
      const tinygltf::Material& src = model_.materials[i];
      SceneMaterial m;
      m.name = src.name.empty() ? format("material%zu", i) : src.name;
      const auto& factor = src.pbrMetallicRoughness.baseColorFactor;
      if (factor.size() == 4) m.base_color_factor = glm::vec4(factor[0], factor[1], factor[2], factor[3]);
      m.double_sided = src.doubleSided;
      m.alpha_mode = src.alphaMode == "MASK"    ? AlphaMode::kMask
                     : src.alphaMode == "BLEND" ? AlphaMode::kBlend
                                                : AlphaMode::kOpaque;
      m.alpha_cutoff = static_cast<float>(src.alphaCutoff);
      const tinygltf::TextureInfo& info = src.pbrMetallicRoughness.baseColorTexture;
      if (info.index >= 0 && static_cast<std::size_t>(info.index) < model_.textures.size()) {
        attach_texture(m, texturing_[i], info, i);
      }
      out_->materials.push_back(std::move(m));
    }
  }

  void attach_texture(SceneMaterial& m, MaterialTexturing& tex, const tinygltf::TextureInfo& info, std::size_t i) {
    const tinygltf::Texture& texture = model_.textures[static_cast<std::size_t>(info.index)];
    int set = info.texCoord;
    if (auto ext = info.extensions.find("KHR_texture_transform"); ext != info.extensions.end()) {
      const tinygltf::Value& t = ext->second;
      UvTransform& uv = m.base_color_uv_transform;
      uv.present = true;
      if (t.Has("offset"))
        uv.offset = glm::vec2(number(t.Get("offset").Get(0), 0.0), number(t.Get("offset").Get(1), 0.0));
      if (t.Has("scale")) uv.scale = glm::vec2(number(t.Get("scale").Get(0), 1.0), number(t.Get("scale").Get(1), 1.0));
      uv.rotation = static_cast<float>(number(t.Get("rotation"), 0.0));
      if (t.Has("texCoord")) set = static_cast<int>(number(t.Get("texCoord"), set));
    }
    std::string reason;
    const int image = texture.source >= 0 ? scene_image(texture.source, &reason) : -1;
    if (texture.source < 0) reason = "has no source image (an unsupported image extension?)";
    if (image < 0) {
      warnings_.add(format("material %zu ('%s'): base colour texture %d %s; using the colour factor", i, m.name.c_str(),
                           info.index, reason.c_str()));
      return;
    }
    m.base_color_image = image;
    if (texture.sampler >= 0 && static_cast<std::size_t>(texture.sampler) < model_.samplers.size()) {
      m.wrap_s = wrap_mode(model_.samplers[static_cast<std::size_t>(texture.sampler)].wrapS);
      m.wrap_t = wrap_mode(model_.samplers[static_cast<std::size_t>(texture.sampler)].wrapT);
    }
    tex.texcoord_set = set;
    tex.transform = m.base_color_uv_transform;
  }

  std::uint32_t default_material() {
    if (default_material_ < 0) {
      default_material_ = static_cast<int>(out_->materials.size());
      SceneMaterial m;
      m.name = "default";
      out_->materials.push_back(m);
    }
    return static_cast<std::uint32_t>(default_material_);
  }

  bool walk(const tinygltf::Scene& scene, int scene_index, std::string* out_error) {
    std::vector<std::uint8_t> visited(model_.nodes.size(), 0);
    node_rest_.assign(model_.nodes.size(), NodeRest{});
    // (node, parent node or -1, parent's world transform)
    std::vector<std::tuple<int, int, glm::dmat4>> stack;
    for (auto it = scene.nodes.rbegin(); it != scene.nodes.rend(); ++it) stack.emplace_back(*it, -1, glm::dmat4(1.0));
    while (!stack.empty()) {
      const auto [index, parent_index, parent] = stack.back();
      stack.pop_back();
      if (index < 0 || static_cast<std::size_t>(index) >= model_.nodes.size()) {
        return fail(format("node %d does not exist", index), out_error);
      }
      if (visited[static_cast<std::size_t>(index)]) {
        return fail(
            format("node %d is reached twice from scene %d (the node hierarchy must be a tree)", index, scene_index),
            out_error);
      }
      visited[static_cast<std::size_t>(index)] = 1;
      const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(index)];
      const glm::dmat4 local = local_transform(node, warnings_, index);
      const glm::dmat4 world = parent * local;
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
          if (!std::isfinite(world[c][r]))
            return fail(format("node %d has a non-finite world transform", index), out_error);
        }
      }
      NodeRest& rest = node_rest_[static_cast<std::size_t>(index)];
      rest.in_scene = true;
      rest.parent = parent_index < 0 ? kNoSceneNode : static_cast<std::uint32_t>(parent_index);
      rest.local = local;
      rest.world = world;
      walk_order_.push_back(static_cast<std::uint32_t>(index));
      if (node.mesh >= 0 && !add_mesh(node, index, world, out_error)) return false;
      if (auto ext = node.extensions.find("KHR_lights_punctual"); ext != node.extensions.end()) {
        const int light = static_cast<int>(number(ext->second.Get("light"), -1.0));
        if (light >= 0 && static_cast<std::size_t>(light) < model_.lights.size()) {
          lights_.push_back(light_from_gltf(model_, light, world, punctual_extents_[static_cast<std::size_t>(light)]));
          lights_.back().node = static_cast<std::uint32_t>(index);
        }
      }
      if (auto ext = node.extensions.find("EXT_lights_area"); ext != node.extensions.end()) {
        if (auto light = area_light_from_gltf(area_defs_, ext->second, index, world, warnings_)) {
          light->node = static_cast<std::uint32_t>(index);
          lights_.push_back(std::move(*light));
        }
      }
      if (node.skin >= 0) ++skinned_nodes_;
      for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.emplace_back(*it, index, world);
    }
    return true;
  }

  bool add_mesh(const tinygltf::Node& node, int node_index, const glm::dmat4& world, std::string* out_error) {
    if (static_cast<std::size_t>(node.mesh) >= model_.meshes.size()) {
      return fail(format("node %d refers to mesh %d, which does not exist", node_index, node.mesh), out_error);
    }
    const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(node.mesh)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& primitive = mesh.primitives[p];
      const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
      const auto key = std::make_pair(node.mesh, static_cast<int>(p));
      const bool first = geometry_ids_.count(key) == 0;
      if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
          mode == TINYGLTF_MODE_LINE_STRIP) {
        if (first) {
          ++(mode == TINYGLTF_MODE_POINTS ? out_->stats.point_primitives_skipped : out_->stats.line_primitives_skipped);
          geometry_ids_[key] = ~0u;
        }
        continue;
      }
      if (!primitive.targets.empty() && first) ++morphed_primitives_;
      PrimitiveContext ctx;
      ctx.mesh = node.mesh;
      ctx.primitive = static_cast<int>(p);
      ctx.node = static_cast<std::uint32_t>(node_index);
      ctx.first_instance = first;
      if (first) geometry_ids_[key] = next_geometry_++;
      ctx.geometry = geometry_ids_[key];
      ctx.T_world_local = world;
      ctx.name = (mesh.name.empty() ? format("mesh%d", node.mesh) : mesh.name) + "/" + std::to_string(p);
      if (primitive.material >= 0 && static_cast<std::size_t>(primitive.material) < texturing_.size()) {
        ctx.material = static_cast<std::uint32_t>(primitive.material);
        const MaterialTexturing& tex = texturing_[static_cast<std::size_t>(primitive.material)];
        ctx.texcoord_set = tex.texcoord_set;
        ctx.texcoord_required = tex.texcoord_set >= 0;
        ctx.uv_transform = tex.transform;
      } else {
        ctx.material = default_material();
      }
      SceneMesh converted;
      if (!convert_primitive(model_, primitive, ctx, budget_, out_->stats, warnings_, &converted, out_error)) {
        return false;
      }
      if (!converted.indices.empty()) out_->meshes.push_back(std::move(converted));
    }
    return true;
  }

  void finish() {
    SceneStats& stats = out_->stats;
    if (stats.point_primitives_skipped + stats.line_primitives_skipped > 0) {
      warnings_.add(format("skipped %u point and %u line primitives (only triangles cast shadows)",
                           stats.point_primitives_skipped, stats.line_primitives_skipped));
    }
    if (skinned_nodes_ > 0)
      warnings_.add(format("%u skinned nodes: skinning is ignored (static pose)", skinned_nodes_));
    if (morphed_primitives_ > 0) {
      warnings_.add(format("%u primitives have morph targets: morphing is ignored (base shape)", morphed_primitives_));
    }
    warn_unimplemented_extensions();
    for (const SceneMesh& mesh : out_->meshes) {
      for (std::uint32_t i : mesh.indices) out_->bounds.extend(mesh.positions[i]);
      out_->triangle_count += mesh.triangle_count();
      out_->vertex_count += mesh.positions.size();
    }
    if (out_->triangle_count == 0) warnings_.add("the scene has no triangles");
    if (lights_.size() > kMaxSceneLights) {
      stats.lights_dropped = static_cast<std::uint32_t>(lights_.size() - kMaxSceneLights);
      warnings_.add(format("the scene has %zu lights; keeping the first %u (beyond 32 they share light slots)", lights_.size(),
                           kMaxSceneLights));
      lights_.resize(kMaxSceneLights);
    }
    out_->lights = std::move(lights_);
    if (out_->lights.empty() && options_.default_lights_when_none) {
      out_->lights = make_default_light_rig(out_->bounds);
      out_->default_lights = true;
      warnings_.add("the scene has no lights; using the default rig of 3 lights");
    }
  }

  // What the file asks for and this loader does not implement is named, never dropped silently (DESIGN 5b).
  void warn_unimplemented_extensions() {
    for (const std::string& name : model_.extensionsUsed) {
      if (extension_implemented(name)) continue;
      warnings_.add(format("extension %s is used but not implemented: what it adds is ignored", name.c_str()));
    }
  }

  const tinygltf::Model& model_;
  const SceneLoadOptions& options_;
  const ImageDecodeContext& images_;
  const LightJson& light_json_;
  WarningSink& warnings_;
  Scene* out_;
  Budget budget_;
  std::vector<MaterialTexturing> texturing_;
  std::map<int, std::pair<int, std::string>> image_map_;
  std::map<std::pair<int, int>, std::uint32_t> geometry_ids_;
  std::uint32_t next_geometry_ = 0;
  int default_material_ = -1;
  std::vector<SceneLight> lights_;  // in node walk order, punctual and area lights alike (kMaxSceneLights applies)
  std::vector<PunctualExtent> punctual_extents_;  // by KHR_lights_punctual index
  std::vector<AreaLightDef> area_defs_;           // by EXT_lights_area index
  std::vector<NodeRest> node_rest_;         // by glTF node index (in_scene: reached by the walk)
  std::vector<std::uint32_t> walk_order_;  // nodes in walk order (parents first)
  std::uint32_t skinned_nodes_ = 0;
  std::uint32_t morphed_primitives_ = 0;
};

}  // namespace

bool build_scene(const tinygltf::Model& model, const SceneLoadOptions& options, const ImageDecodeContext& images,
                 const LightJson& light_json, WarningSink& warnings, Scene* out, std::string* out_error) {
  return Builder(model, options, images, light_json, warnings, out).run(out_error);
}

}  // namespace dhr::scene_detail
