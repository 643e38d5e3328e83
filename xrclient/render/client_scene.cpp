#include "render/client_scene.hpp"

#include <algorithm>
#include <array>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

#include "vk/check.hpp"
#include "vk/context.hpp"

namespace dhr::render {
namespace {

VkSamplerAddressMode address_mode(TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::kClampToEdge: return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    case TextureWrap::kMirroredRepeat: return VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT;
    case TextureWrap::kRepeat: break;
  }
  return VK_SAMPLER_ADDRESS_MODE_REPEAT;
}

vk::Sampler create_sampler(VkDevice device, TextureWrap wrap_s, TextureWrap wrap_t) {
  VkSamplerCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO;
  info.magFilter = VK_FILTER_LINEAR;
  info.minFilter = VK_FILTER_LINEAR;
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  info.addressModeU = address_mode(wrap_s);
  info.addressModeV = address_mode(wrap_t);
  info.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
  info.maxLod = 0.0f;
  VkSampler sampler = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkCreateSampler(device, &info, nullptr, &sampler));
  return vk::Sampler(device, sampler);
}

vk::Image upload_texture(const vk::Context& context, uint32_t width, uint32_t height, const uint8_t* rgba8) {
  vk::Image image(context, width, height, VK_FORMAT_R8G8B8A8_SRGB,
                  VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
  vk::upload_image(context, image, rgba8, size_t{width} * height * 4);
  return image;
}

// Centre and radius of a mesh's bounds, in double (the positions are float world coordinates).
std::pair<glm::dvec3, double> mesh_sphere(const SceneMesh& mesh) {
  glm::dvec3 lo(std::numeric_limits<double>::max());
  glm::dvec3 hi(std::numeric_limits<double>::lowest());
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  if (mesh.positions.empty()) return {glm::dvec3(0.0), 0.0};
  const glm::dvec3 centre = 0.5 * (lo + hi);
  return {centre, 0.5 * glm::length(hi - lo)};
}

}  // namespace

ClientScene::ClientScene(const vk::Context& context, const Scene& scene)
    : lights_(scene.lights), light_slots_(LightSlots::assign(scene.lights)), bounds_(scene.bounds) {
  if (!light_slots_.is_identity() && !scene.animation.empty()) {
    throw std::invalid_argument("client scene: " + std::to_string(lights_.size()) +
                                " lights share light slots, which need a scene without animation");
  }
  field_lights_ = light_slots_.field_lights(lights_);
  // Textures: index 0 is white for untextured materials; scene image i is texture i + 1.
  const std::array<uint8_t, 4> white = {255, 255, 255, 255};
  textures_.push_back(upload_texture(context, 1, 1, white.data()));
  for (const SceneImage& image : scene.images) {
    if (image.width == 0 || image.height == 0 || image.rgba8.size() != size_t{image.width} * image.height * 4) {
      throw std::invalid_argument("scene image '" + image.name + "' has no or inconsistent RGBA8 pixels");
    }
    textures_.push_back(upload_texture(context, image.width, image.height, image.rgba8.data()));
  }

  std::map<std::pair<TextureWrap, TextureWrap>, uint32_t> sampler_index;
  for (const SceneMaterial& m : scene.materials) {
    ClientMaterial out;
    out.base_color_factor = m.base_color_factor;
    if (m.base_color_image >= 0) {
      if (static_cast<size_t>(m.base_color_image) >= scene.images.size()) {
        throw std::invalid_argument("material '" + m.name + "' refers to a missing image");
      }
      out.texture = static_cast<uint32_t>(m.base_color_image) + 1;
    }
    const auto key = std::make_pair(m.wrap_s, m.wrap_t);
    auto it = sampler_index.find(key);
    if (it == sampler_index.end()) {
      it = sampler_index.emplace(key, static_cast<uint32_t>(samplers_.size())).first;
      samplers_.push_back(create_sampler(context.device(), m.wrap_s, m.wrap_t));
    }
    out.sampler = it->second;
    out.double_sided = m.double_sided;
    out.alpha_mask = m.alpha_mode == AlphaMode::kMask;
    out.alpha_cutoff = m.alpha_cutoff;
    materials_.push_back(out);
  }

  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> texcoords;
  std::vector<uint32_t> indices;
  for (uint32_t source = 0; source < scene.meshes.size(); ++source) {
    const SceneMesh& mesh = scene.meshes[source];
    if (mesh.indices.empty()) continue;
    if (mesh.normals.size() != mesh.positions.size() ||
        (!mesh.texcoords.empty() && mesh.texcoords.size() != mesh.positions.size())) {
      throw std::invalid_argument("mesh '" + mesh.name + "': normals/texcoords do not match its positions");
    }
    if (mesh.material >= materials_.size()) {
      throw std::invalid_argument("mesh '" + mesh.name + "' refers to a missing material");
    }
    if (mesh.indices.size() % 3 != 0 ||
        *std::max_element(mesh.indices.begin(), mesh.indices.end()) >= mesh.positions.size()) {
      throw std::invalid_argument("mesh '" + mesh.name + "' has an incomplete triangle or an index out of range");
    }
    if (positions.size() + mesh.positions.size() > static_cast<size_t>(std::numeric_limits<int32_t>::max()) ||
        indices.size() + mesh.indices.size() > std::numeric_limits<uint32_t>::max()) {
      throw std::invalid_argument("scene too large for 32-bit draw offsets");
    }
    ClientMesh out;
    out.name = mesh.name;
    out.first_index = static_cast<uint32_t>(indices.size());
    out.index_count = static_cast<uint32_t>(mesh.indices.size());
    out.vertex_offset = static_cast<int32_t>(positions.size());
    out.material = mesh.material;
    out.source = source;
    std::tie(out.origin, out.radius) = mesh_sphere(mesh);
    for (const glm::vec3& p : mesh.positions) positions.emplace_back(glm::dvec3(p) - out.origin);
    normals.insert(normals.end(), mesh.normals.begin(), mesh.normals.end());
    if (mesh.texcoords.empty()) {
      texcoords.resize(texcoords.size() + mesh.positions.size(), glm::vec2(0.0f));
    } else {
      texcoords.insert(texcoords.end(), mesh.texcoords.begin(), mesh.texcoords.end());
    }
    indices.insert(indices.end(), mesh.indices.begin(), mesh.indices.end());
    triangle_count_ += mesh.indices.size() / 3;
    meshes_.push_back(std::move(out));
  }
  motion_ = ClientMotion(scene, meshes_);
  if (indices.empty()) return;
  positions_ = vk::create_buffer_with_data(context, std::span<const glm::vec3>(positions),
                                           VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  normals_ = vk::create_buffer_with_data(context, std::span<const glm::vec3>(normals),
                                         VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  texcoords_ = vk::create_buffer_with_data(context, std::span<const glm::vec2>(texcoords),
                                           VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  indices_ = vk::create_buffer_with_data(context, std::span<const uint32_t>(indices),
                                         VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
}

namespace {

constexpr std::array<VkVertexInputBindingDescription, 3> kVertexBindings = {{
    {0, sizeof(float) * 3, VK_VERTEX_INPUT_RATE_VERTEX},
    {1, sizeof(float) * 3, VK_VERTEX_INPUT_RATE_VERTEX},
    {2, sizeof(float) * 2, VK_VERTEX_INPUT_RATE_VERTEX},
}};
constexpr std::array<VkVertexInputAttributeDescription, 3> kVertexAttributes = {{
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
    {1, 1, VK_FORMAT_R32G32B32_SFLOAT, 0},
    {2, 2, VK_FORMAT_R32G32_SFLOAT, 0},
}};

}  // namespace

std::span<const VkVertexInputBindingDescription> ClientScene::vertex_bindings() { return kVertexBindings; }

std::span<const VkVertexInputAttributeDescription> ClientScene::vertex_attributes() { return kVertexAttributes; }

std::span<const VkVertexInputBindingDescription> ClientScene::position_bindings() {
  return std::span(kVertexBindings).first(1);
}

std::span<const VkVertexInputAttributeDescription> ClientScene::position_attributes() {
  return std::span(kVertexAttributes).first(1);
}

void ClientScene::bind_geometry(VkCommandBuffer cmd) const {
  const std::array<VkBuffer, 3> buffers = {positions_.handle(), normals_.handle(), texcoords_.handle()};
  const std::array<VkDeviceSize, 3> offsets = {0, 0, 0};
  vkCmdBindVertexBuffers(cmd, 0, static_cast<uint32_t>(buffers.size()), buffers.data(), offsets.data());
  vkCmdBindIndexBuffer(cmd, indices_.handle(), 0, VK_INDEX_TYPE_UINT32);
}

}  // namespace dhr::render
