#include "render/shadow_maps.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <limits>
#include <stdexcept>

#include "dhr_shaders_client.hpp"
#include "render/client_scene.hpp"
#include "render/mesh_push.hpp"
#include "render/pass_util.hpp"
#include "render/render_camera.hpp"
#include "render/scene_draw.hpp"
#include "render/client_motion.hpp"
#include "render/shadow_refresh.hpp"
#include "render/sun_map.hpp"
#include "shaders/shader_interface.h"
#include "vk/barriers.hpp"
#include "vk/context.hpp"
#include "vk/graphics_pipeline.hpp"
#include "vk/pipeline.hpp"

namespace dhr::render {
namespace {

// (right, up) of each face; forward = up x right (right x up = backward).
constexpr std::array<std::array<glm::dvec3, 2>, 6> kFaceAxes = {{
    {glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0)},    // +X
    {glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0)},   // -X
    {glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1)},    // +Y
    {glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1)},   // -Y
    {glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0)},   // +Z
    {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)},    // -Z
}};


uint32_t max_image_dimension(const vk::Context& context) {
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(context.physical_device(), &properties);
  return properties.limits.maxImageDimension2D;
}

}  // namespace

Camera cube_face_camera(const glm::dvec3& light, uint32_t face, uint32_t size) {
  if (face >= 6) throw std::invalid_argument("cube_face_camera: face must be 0-5");
  const glm::dvec3 right = kFaceAxes[face][0];
  const glm::dvec3 up = kFaceAxes[face][1];
  const glm::dvec3 back = glm::cross(right, up);
  Camera camera;
  camera.T_world_eye.position = light;
  camera.T_world_eye.orientation = glm::normalize(glm::quat_cast(glm::dmat3(right, up, back)));
  camera.tangents = Tangents{-1.0, 1.0, 1.0, -1.0};
  camera.extent = Extent{size, size};
  return camera;
}

ShadowMaps::ShadowMaps(const vk::Context& context, const ClientScene& scene, const ShadowMapSettings& settings)
    : context_(&context), scene_(&scene), settings_(settings) {
  if (settings.size == 0) throw std::invalid_argument("shadow maps: the face size must be at least 1");
  if (!(settings.near_plane > 0.0)) throw std::invalid_argument("shadow maps: the near plane must be > 0");
  const VkDevice device = context.device();
  const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(shader::ClientGBufferPush)};
  layout_ = vk::create_pipeline_layout(device, {}, std::span(&push, 1));
  vk::GraphicsPipelineDesc desc;
  desc.vertex = &vk::find_spirv(dhr_shaders_client_modules(), "shadow_depth.vert");
  desc.vertex_bindings = ClientScene::position_bindings();
  desc.vertex_attributes = ClientScene::position_attributes();
  desc.depth_format = VK_FORMAT_D32_SFLOAT;
  desc.depth_compare = VK_COMPARE_OP_GREATER;
  desc.cull_mode = VK_CULL_MODE_NONE;  // shadow rays hit either side
  pipeline_ = vk::create_graphics_pipeline(device, layout_.get(), desc);
  render(scene.lights());
}

ShadowTile ShadowMaps::tile_for(const SceneLight& light, std::optional<uint32_t> row) const {
  ShadowTile tile;
  tile.position = glm::dvec3(light.position);
  tile.row = row;
  if (light.type == SceneLight::Type::kDirectional && row) {
    tile.sun = fit_sun_map(scene_->bounds(), glm::dvec3(light.direction));
    tile.position = tile.sun->position;
  }
  return tile;
}

void ShadowMaps::render(std::span<const SceneLight> lights) {
  const auto start = std::chrono::steady_clock::now();
  tiles_.clear();
  uint32_t rows = 0;
  for (const SceneLight& light : lights) {
    // Point, spot, sphere, rect and disk lights: a cube map at the light's centre (where the hard-shadow ray goes);
    // a sun: an orthographic tile; other directional lights: none.
    const bool mapped = light.type != SceneLight::Type::kDirectional || light.angle > 0.0f;
    tiles_.push_back(tile_for(light, mapped ? std::optional<uint32_t>(rows++) : std::nullopt));
  }
  const uint32_t max_dim = max_image_dimension(*context_);
  size_ = std::max<uint32_t>(1, std::min({settings_.size, max_dim / 6, rows > 0 ? max_dim / rows : max_dim}));
  const uint32_t width = 6 * size_, height = std::max<uint32_t>(1, rows) * size_;
  if (!atlas_ || atlas_.width() != width || atlas_.height() != height) {
    atlas_ = vk::Image(*context_, width, height, VK_FORMAT_D32_SFLOAT,
                       VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                           VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
  }
  const ClientScene& scene = *scene_;
  const bool split = settings_.split_static && scene.motion().animated() && scene.indices() && rows > 0;
  if (!split) {
    static_atlas_ = vk::Image();
  } else if (!static_atlas_ || static_atlas_.width() != width || static_atlas_.height() != height) {
    static_atlas_ = vk::Image(*context_, width, height, VK_FORMAT_D32_SFLOAT,
                              VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  }
  context_->submit_and_wait([&](VkCommandBuffer cmd) {
    discard_to_layout(cmd, atlas_, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    VkClearValue nothing{};
    nothing.depthStencil = {0.0f, 0};  // reversed-Z: nothing
    const VkRenderingAttachmentInfo depth =
        cleared_attachment(atlas_.view(), VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, nothing);
    begin_rendering(cmd, width, height, {}, &depth);
    if (scene.indices() && rows > 0) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
      scene.bind_geometry(cmd);
      for (const ShadowTile& tile : tiles_) {
        if (!tile.row) continue;
        for (uint32_t face = 0; face < (tile.sun ? 1u : 6u); ++face) draw_face(cmd, tile, face, nullptr);
      }
    }
    vkCmdEndRendering(cmd);
    atlas_.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    if (split) {  // the same faces with the static casters alone
      discard_to_layout(cmd, static_atlas_, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                        VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
      const VkRenderingAttachmentInfo static_depth =
          cleared_attachment(static_atlas_.view(), VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, nothing);
      begin_rendering(cmd, width, height, {}, &static_depth);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
      scene.bind_geometry(cmd);
      for (const ShadowTile& tile : tiles_) {
        if (!tile.row) continue;
        for (uint32_t face = 0; face < (tile.sun ? 1u : 6u); ++face) draw_face(cmd, tile, face, nullptr, Casters::kStatic);
      }
      vkCmdEndRendering(cmd);
      static_atlas_.transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    }
  });
  // Which faces hold a moving mesh at rest (the first update re-renders those).
  held_.assign(tiles_.size(), 0);
  stale_.assign(tiles_.size(), 0);
  split_faces_.assign(tiles_.size(), 0);
  pending_.assign(tiles_.size(), 0);
  turn_.assign(tiles_.size(), std::numeric_limits<int64_t>::min());
  if (scene.motion().animated() && lights.size() == scene.lights().size()) {
    std::vector<glm::dvec3> centre;
    std::vector<double> radius;
    for (const ClientMesh& mesh : scene.meshes()) {
      centre.push_back(mesh.origin);
      radius.push_back(mesh.radius);
    }
    for (size_t l = 0; l < tiles_.size(); ++l) {
      held_[l] = faces_seeing_motion(tiles_[l], lights[l], scene.motion(), MeshSpheres{centre, radius}, size_);
    }
  }
  render_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Whether light l's map takes its turn now: the period of scene time (at the light's phase) it falls in differs
// from the one it was last rendered in. Every time without a period, and when told to (all_now).
bool ShadowMaps::takes_turn(size_t l, const ShadowRefresh& refresh) {
  if (refresh.period_ns <= 0) {
    turn_[l] = std::numeric_limits<int64_t>::min();  // the next staggered update re-renders what is pending
    return true;
  }
  const int64_t phase = refresh.period_ns / static_cast<int64_t>(tiles_.size()) * static_cast<int64_t>(l);
  const int64_t t = refresh.scene_time_ns + phase;
  const int64_t turn = t / refresh.period_ns - (t % refresh.period_ns < 0 ? 1 : 0);  // floor
  if (turn == turn_[l] && !refresh.all_now) return false;
  turn_[l] = turn;
  return true;
}

ShadowUpdate ShadowMaps::update(VkCommandBuffer cmd, const MovedScene& moved, const ShadowRefresh& refresh) {
  ShadowUpdate out;
  const ClientScene& scene = *scene_;
  const ClientMotion& motion = scene.motion();
  if (!motion.animated() || !moved.sampled || !scene.indices() || moved.lights.size() != tiles_.size()) return out;
  const MeshSpheres spheres{moved.centre, moved.radius};
  for (size_t l = 0; l < tiles_.size(); ++l) {
    stale_[l] = 0;
    split_faces_[l] = 0;
    if (!tiles_[l].row) continue;
    const bool light_moves = motion.light_moves(static_cast<uint32_t>(l));
    const bool turn = takes_turn(l, refresh);
    // A moving light's map moves with it when re-rendered; until then it stays where it was rendered.
    if (light_moves && turn) tiles_[l] = tile_for(moved.lights[l], tiles_[l].row);
    const uint8_t seeing = faces_seeing_motion(tiles_[l], moved.lights[l], motion, spheres, size_);
    pending_[l] |= stale_faces(tiles_[l], light_moves, seeing, held_[l]);
    if (!turn) continue;
    stale_[l] = pending_[l];
    pending_[l] = 0;
    // A light that stays put: its static casters are where they were, so the static atlas holds them.
    split_faces_[l] = static_atlas_ && !light_moves ? stale_[l] : uint8_t{0};
    // What the faces hold now: those re-rendered, what they see; the others, what they held.
    held_[l] = static_cast<uint8_t>((seeing & stale_[l]) | (held_[l] & ~stale_[l]));
    if (stale_[l] == 0) continue;
    ++out.lights;
    for (uint32_t face = 0; face < 6; ++face) out.faces += (stale_[l] >> face) & 1u;
  }
  if (out.faces == 0) return out;
  // Keep the other faces: wait for earlier readers, load, clear only the stale faces (or copy their static casters).
  if (!copy_static_faces(cmd)) {
    vk::image_barrier(cmd, atlas_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, atlas_.layout(),
                      VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE,
                      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    atlas_.set_layout(VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
  }
  VkRenderingAttachmentInfo depth{};
  depth.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
  depth.imageView = atlas_.view();
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  begin_rendering(cmd, stale_area(), {}, &depth);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
  scene.bind_geometry(cmd);
  VkClearAttachment clear{};
  clear.aspectMask = VK_IMAGE_ASPECT_DEPTH_BIT;
  clear.clearValue.depthStencil = {0.0f, 0};  // reversed-Z: nothing
  for (size_t l = 0; l < tiles_.size(); ++l) {
    for (uint32_t face = 0; face < 6; ++face) {
      if (((stale_[l] >> face) & 1u) == 0) continue;
      if ((split_faces_[l] >> face) & 1u) {  // the static casters are copied in: add the moving ones
        draw_face(cmd, tiles_[l], face, &moved, Casters::kMoving);
        continue;
      }
      const VkClearRect rect{{{static_cast<int32_t>(face * size_), static_cast<int32_t>(*tiles_[l].row * size_)},
                              {size_, size_}},
                             0, 1};
      vkCmdClearAttachments(cmd, 1, &clear, 1, &rect);
      draw_face(cmd, tiles_[l], face, &moved);
    }
  }
  vkCmdEndRendering(cmd);
  atlas_.transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  return out;
}

VkRect2D ShadowMaps::stale_area() const {
  uint32_t x0 = 6, x1 = 0, y0 = std::numeric_limits<uint32_t>::max(), y1 = 0;  // in faces
  for (size_t l = 0; l < tiles_.size(); ++l) {
    if (stale_[l] == 0) continue;
    for (uint32_t face = 0; face < 6; ++face) {
      if (((stale_[l] >> face) & 1u) == 0) continue;
      x0 = std::min(x0, face);
      x1 = std::max(x1, face + 1);
    }
    y0 = std::min(y0, *tiles_[l].row);
    y1 = std::max(y1, *tiles_[l].row + 1);
  }
  if (x1 <= x0 || y1 <= y0) return VkRect2D{{0, 0}, {0, 0}};
  return VkRect2D{{static_cast<int32_t>(x0 * size_), static_cast<int32_t>(y0 * size_)},
                  {(x1 - x0) * size_, (y1 - y0) * size_}};
}

bool ShadowMaps::drawn(uint32_t mesh, Casters casters) const {
  if (casters == Casters::kAll) return true;
  return scene_->motion().mesh_moves(mesh) == (casters == Casters::kMoving);
}

bool ShadowMaps::copy_static_faces(VkCommandBuffer cmd) {
  std::vector<VkImageCopy>& regions = copies_;
  regions.clear();
  for (size_t l = 0; l < tiles_.size(); ++l) {
    for (uint32_t face = 0; face < 6; ++face) {
      if (((split_faces_[l] >> face) & 1u) == 0) continue;
      VkImageCopy region{};
      region.srcSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1};
      region.dstSubresource = region.srcSubresource;
      region.srcOffset = {static_cast<int32_t>(face * size_), static_cast<int32_t>(*tiles_[l].row * size_), 0};
      region.dstOffset = region.srcOffset;
      region.extent = {size_, size_, 1};
      regions.push_back(region);
    }
  }
  if (regions.empty()) return false;
  // Earlier readers of the atlas (previous frames' lookups) finish before the copy overwrites those faces.
  vk::image_barrier(cmd, atlas_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, atlas_.layout(),
                    VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE,
                    VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdCopyImage(cmd, static_atlas_.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, atlas_.handle(),
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, static_cast<uint32_t>(regions.size()), regions.data());
  vk::image_barrier(cmd, atlas_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  atlas_.set_layout(VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
  return true;
}

void ShadowMaps::draw_face(VkCommandBuffer cmd, const ShadowTile& tile, uint32_t face, const MovedScene* moved,
                           Casters casters) const {
  if (tile.sun) {
    render_sun(cmd, tile, moved, casters);
    return;
  }
  const Camera camera = cube_face_camera(tile.position, face, size_);
  const VkViewport viewport{static_cast<float>(face * size_), static_cast<float>(*tile.row * size_),
                            static_cast<float>(size_), static_cast<float>(size_), 0.0f, 1.0f};
  const VkRect2D scissor{{static_cast<int32_t>(face * size_), static_cast<int32_t>(*tile.row * size_)},
                         {size_, size_}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  shader::ClientGBufferPush push{};
  const MeshPush transform(camera_relative_view_projection(camera, settings_.near_plane), tile.position);
  const ClientScene& scene = *scene_;
  for (uint32_t i = 0; i < scene.meshes().size(); ++i) {
    if (!drawn(i, casters)) continue;
    const ClientMesh& mesh = scene.meshes()[i];
    const glm::dmat4* motion = moved_motion(scene, moved, i);
    if (!sphere_may_be_visible(camera, motion ? moved->centre[i] : mesh.origin,
                               motion ? moved->radius[i] : mesh.radius)) {
      continue;
    }
    transform.set(push, mesh, motion);
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), &push);
    vkCmdDrawIndexed(cmd, mesh.index_count, 1, mesh.first_index, mesh.vertex_offset, 0);
  }
}

void ShadowMaps::render_sun(VkCommandBuffer cmd, const ShadowTile& tile, const MovedScene* moved,
                            Casters casters) const {
  const VkViewport viewport{0.0f, static_cast<float>(*tile.row * size_), static_cast<float>(size_),
                            static_cast<float>(size_), 0.0f, 1.0f};
  const VkRect2D scissor{{0, static_cast<int32_t>(*tile.row * size_)}, {size_, size_}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  shader::ClientGBufferPush push{};
  const MeshPush transform(sun_view_projection(*tile.sun), tile.sun->position);
  const ClientScene& scene = *scene_;
  for (uint32_t i = 0; i < scene.meshes().size(); ++i) {  // the tile covers the whole scene: no culling
    if (!drawn(i, casters)) continue;
    const ClientMesh& mesh = scene.meshes()[i];
    transform.set(push, mesh, moved_motion(scene, moved, i));
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), &push);
    vkCmdDrawIndexed(cmd, mesh.index_count, 1, mesh.first_index, mesh.vertex_offset, 0);
  }
}

}  // namespace dhr::render
