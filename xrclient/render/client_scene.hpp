// A Scene uploaded for rasterization: concatenated vertex streams (position, normal, uv) and indices,
// per-mesh draw ranges, materials, base-colour textures (sRGB RGBA8 + samplers), all in dhr_vk RAII owners.
// Positions are stored relative to their mesh's origin (the centre of its bounds, in double), so the
// G-buffer pass can add a per-draw (origin - eye) offset and never handle world coordinates on the GPU.
// motion() says what moves (client_motion.hpp); the rest data here is the scene at rest.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

#include "render/client_motion.hpp"
#include "scene/light_slots.hpp"
#include "scene/scene.hpp"
#include "vk/buffer.hpp"
#include "vk/handle.hpp"
#include "vk/image.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

struct ClientMesh {
  std::string name;
  uint32_t first_index = 0;  // into ClientScene::indices()
  uint32_t index_count = 0;
  int32_t vertex_offset = 0;  // added to each index
  uint32_t material = 0;      // into ClientScene::materials()
  glm::dvec3 origin{0.0};     // world; the mesh's positions are uploaded relative to it
  double radius = 0.0;        // bounding sphere around origin (frustum culling)
  uint32_t source = 0;        // index into the Scene's meshes (a mesh without triangles is not uploaded)
};

struct ClientMaterial {
  glm::vec4 base_color_factor{1.0f};  // linear RGBA
  uint32_t texture = 0;               // into ClientScene::textures(); 0: 1x1 white (untextured)
  uint32_t sampler = 0;               // into ClientScene::samplers()
  bool double_sided = false;
  bool alpha_mask = false;  // glTF alphaMode MASK (BLEND is drawn opaque)
  float alpha_cutoff = 0.5f;
};

class ClientScene {
 public:
  // Blocks while uploading. Throws std::invalid_argument for an inconsistent Scene (a mesh whose normals
  // or texcoords do not match its positions, a bad material or index), more than kMaxSlotLights lights or more
  // than kMaxLights in a scene with animation (light slots are placed at rest), dhr::vk::VulkanError on failure.
  ClientScene(const vk::Context& context, const Scene& scene);

  // VERTEX_BUFFER: vec3 positions (mesh-relative), vec3 world normals, vec2 uvs; INDEX_BUFFER: uint32.
  // Null buffers when the scene has no triangles.
  const vk::Buffer& positions() const { return positions_; }
  const vk::Buffer& normals() const { return normals_; }
  const vk::Buffer& texcoords() const { return texcoords_; }
  const vk::Buffer& indices() const { return indices_; }

  // The vertex streams as a graphics pipeline reads them (bindings and locations 0-2: position, normal, uv),
  // and binding them with the index buffer (scenes with triangles only).
  static std::span<const VkVertexInputBindingDescription> vertex_bindings();
  static std::span<const VkVertexInputAttributeDescription> vertex_attributes();
  // The positions' stream alone (binding 0, location 0): depth-only passes (the shadow maps).
  static std::span<const VkVertexInputBindingDescription> position_bindings();
  static std::span<const VkVertexInputAttributeDescription> position_attributes();
  void bind_geometry(VkCommandBuffer cmd) const;

  const std::vector<ClientMesh>& meshes() const { return meshes_; }
  const std::vector<ClientMaterial>& materials() const { return materials_; }
  const std::vector<vk::Image>& textures() const { return textures_; }  // R8G8B8A8_SRGB, SHADER_READ_ONLY
  const std::vector<vk::Sampler>& samplers() const { return samplers_; }
  const std::vector<SceneLight>& lights() const { return lights_; }
  // The mask's fields (scene/light_slots.hpp): the identity for at most kMaxLights lights, else the slots the
  // lights share, derived as the server derives them; field_lights() one light per field (LightSlots::field_lights).
  const LightSlots& light_slots() const { return light_slots_; }
  const std::vector<SceneLight>& field_lights() const { return field_lights_; }
  const SceneBounds& bounds() const { return bounds_; }  // at rest
  // Which meshes and lights move, their rest bounds, and sampling them at a scene time.
  const ClientMotion& motion() const { return motion_; }
  uint64_t triangle_count() const { return triangle_count_; }

 private:
  vk::Buffer positions_;
  vk::Buffer normals_;
  vk::Buffer texcoords_;
  vk::Buffer indices_;
  std::vector<ClientMesh> meshes_;
  std::vector<ClientMaterial> materials_;
  std::vector<vk::Image> textures_;
  std::vector<vk::Sampler> samplers_;
  std::vector<SceneLight> lights_;
  LightSlots light_slots_;
  std::vector<SceneLight> field_lights_;
  SceneBounds bounds_;
  ClientMotion motion_;
  uint64_t triangle_count_ = 0;
};

}  // namespace dhr::render
