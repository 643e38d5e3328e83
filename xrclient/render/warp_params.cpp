#include "render/warp_params.hpp"

#include "render/soft_bands.hpp"
#include "render/warp_edges.hpp"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <vector>

#include "render/light_layout.hpp"
#include "render/render_camera.hpp"
#include "render/shadow_maps.hpp"
#include "render/warp_reference.hpp"
#include "scene/lighting.hpp"
#include "vk/context.hpp"

namespace dhr::render {

using namespace dhr::shader;

namespace {

constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;

void copy3(const glm::dvec3& v, float* out) {
  out[0] = static_cast<float>(v.x);
  out[1] = static_cast<float>(v.y);
  out[2] = static_cast<float>(v.z);
}

// The display camera's pixel rays (tangent-plane point of pixel (0, 0)'s corner and the per-pixel steps),
// rotated by `m` into another frame.
void display_rays(const Camera& display, const glm::dmat3& m, float* ray0, float* ray_dx, float* ray_dy) {
  const Tangents& nt = display.tangents;
  copy3(m * glm::dvec3(nt.left, nt.up, -1.0), ray0);
  copy3(m * glm::dvec3(nt.width() / display.extent.width, 0.0, 0.0), ray_dx);
  copy3(m * glm::dvec3(0.0, -nt.height() / display.extent.height, 0.0), ray_dy);
}

}  // namespace

ClientWarpSource make_warp_source(const Camera& display, const Camera* traced) {
  ClientWarpSource src{};
  const Camera& old_camera = traced != nullptr ? *traced : display;
  const glm::dmat3 r_old_t = glm::transpose(eye_to_world_rotation(old_camera));
  // New eye space -> old eye space.
  display_rays(display, r_old_t * eye_to_world_rotation(display), src.ray0, src.ray_dx, src.ray_dy);
  copy3(r_old_t * (display.T_world_eye.position - old_camera.T_world_eye.position), src.trans);
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) src.rot[row * 3 + col] = static_cast<float>(r_old_t[col][row]);
  }
  const Tangents& ot = old_camera.tangents;
  const double sx = old_camera.extent.width / ot.width();
  const double sy = old_camera.extent.height / ot.height();
  src.old_px_scale = static_cast<float>(sx);
  src.old_px_offset = static_cast<float>(-ot.left * sx);
  src.old_py_scale = static_cast<float>(-sy);
  src.old_py_offset = static_cast<float>(ot.up * sy);
  src.old_tan_left = static_cast<float>(ot.left);
  src.old_tan_up = static_cast<float>(ot.up);
  src.old_tan_step_x = static_cast<float>(ot.width() / old_camera.extent.width);
  src.old_tan_step_y = static_cast<float>(ot.height() / old_camera.extent.height);
  // Without visibility the (clamped) lookups read the 4-byte placeholder buffer's first word.
  src.old_width = traced != nullptr ? traced->extent.width : 1u;
  src.old_height = traced != nullptr ? traced->extent.height : 1u;
  src.mask_bits = 32u;
  return src;
}

ClientWarpParams make_warp_params(const Camera& display, const Camera* traced, double near_plane) {
  ClientWarpParams params{};
  const Camera& old_camera = traced != nullptr ? *traced : display;
  display_rays(display, eye_to_world_rotation(display), params.world_ray0, params.world_ray_dx,
               params.world_ray_dy);
  // Where pixel centre c would land with the new pose equal to source 0's (motion = lookup - this).
  const Tangents& nt = display.tangents;
  const double dx = nt.width() / display.extent.width;
  const double dy = -nt.height() / display.extent.height;
  const Tangents& ot = old_camera.tangents;
  const double sx = old_camera.extent.width / ot.width();
  const double sy = old_camera.extent.height / ot.height();
  const double ox = -ot.left * sx, oy = ot.up * sy;
  params.ident_px_scale = static_cast<float>(sx * dx);
  params.ident_px_offset = static_cast<float>(sx * nt.left + ox);
  params.ident_py_scale = static_cast<float>(-sy * dy);
  params.ident_py_offset = static_cast<float>(-sy * nt.up + oy);
  params.near_plane = static_cast<float>(near_plane);
  params.min_depth = static_cast<float>(kWarpMinDepth);
  params.width = display.extent.width;
  params.height = display.extent.height;
  params.unknown_mask = 0xFFFFFFFFu;
  return params;
}


void describe_shadow_maps(const ShadowMaps& maps, std::span<const SceneLight> lights, const Camera& display,
                          ClientWarpParams& params, std::array<ClientShadowLight, kMaxLights>& shadow_lights) {
  if (lights.size() > kMaxLights || lights.size() != maps.tiles().size()) {
    throw std::invalid_argument("the lights differ from the shadow maps'");
  }
  const glm::dvec3 eye = display.T_world_eye.position;
  const VisibilityLayout layout = layout_for_lights(lights);
  for (size_t i = 0; i < lights.size(); ++i) {
    const ShadowTile& tile = maps.tiles()[i];
    copy3(tile.position - eye, shadow_lights[i].position);
    shadow_lights[i].tile_row = tile.row ? *tile.row : kClientNoShadowMap;
    shadow_lights[i].mask_offset = layout.offset[i];
    shadow_lights[i].mask_bits = layout.bits[i];
    shadow_lights[i].radius = layout.is_soft(static_cast<uint32_t>(i)) ? static_cast<float>(pcss_light_radius(lights[i])) : 0.0f;
    if (tile.sun) {
      shadow_lights[i].flags = kClientShadowSun;
      copy3(tile.sun->right, shadow_lights[i].right);
      copy3(tile.sun->up, shadow_lights[i].up);
      shadow_lights[i].half_extent = static_cast<float>(tile.sun->half_extent);
      shadow_lights[i].depth_range = static_cast<float>(tile.sun->depth_range);
    }
  }
  params.light_count = static_cast<uint32_t>(lights.size());
  params.shadow_size = maps.face_size();
  params.shadow_near = static_cast<float>(maps.settings().near_plane);
  params.shadow_bias_rel = static_cast<float>(maps.settings().bias_rel);
  params.shadow_bias_abs = static_cast<float>(maps.settings().bias_abs);
  params.shadow_normal_offset = static_cast<float>(maps.settings().normal_offset);
  params.shadow_bias_slope = static_cast<float>(maps.settings().bias_slope);
  params.pixel_tangent = static_cast<float>(display.tangents.width() / display.extent.width);
}

uint32_t warp_count_words(Extent extent) {
  const uint32_t groups_x = (extent.width + kClientWarpGroupSize - 1) / kClientWarpGroupSize;
  const uint32_t groups_y = (extent.height + kClientWarpGroupSize - 1) / kClientWarpGroupSize;
  return kClientCountWords * ((groups_x + kClientCountBucketGroups - 1) / kClientCountBucketGroups) * groups_y;
}

WarpCounts unpack_warp_counts(const vk::Buffer& counters, uint32_t words) {
  WarpCounts counts;
  std::array<uint64_t, kClientCountWords * 3> fields{};
  // In chunks through a fixed array: no allocation per frame (thousands of buckets at headset sizes).
  std::array<uint32_t, kClientCountWords * 100> raw{};
  static_assert(raw.size() % kClientCountWords == 0, "chunks hold whole buckets");
  for (uint32_t first = 0; first < words; first += static_cast<uint32_t>(raw.size())) {
    const uint32_t n = std::min<uint32_t>(static_cast<uint32_t>(raw.size()), words - first);
    counters.read(raw.data(), VkDeviceSize{n} * 4, VkDeviceSize{first} * 4);
    for (uint32_t i = 0; i < n; ++i) {
      for (uint32_t field = 0; field < 3; ++field) {
        fields[(i % kClientCountWords) * 3 + field] += (raw[i] >> (10 * field)) & 1023u;
      }
    }
  }
  for (size_t s = 0; s < kWarpStatusCount; ++s) counts.by_status[s] = fields[s];
  counts.filled_other_eye = fields[kClientCountOtherEye];
  counts.filled_shadow_map = fields[kClientCountShadowMap];
  counts.edges_shadow_map = fields[kClientCountEdgeShadowMap];
  counts.shadow_overrides = fields[kClientCountShadowOverride];
  counts.filled_older = fields[kClientCountOlder];
  counts.filled_neighbour = fields[kClientCountNeighbour];
  counts.motion_unknown = fields[kClientCountMotion];
  return counts;
}

WarpSourceBuffers::WarpSourceBuffers(const vk::Context& context)
    : visibility(context, 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost),
      rows(context, kRowWords * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost) {}

void WarpSourceBuffers::upload(const vk::Context& context, const Camera& display, const VisibilityInput& input,
                               ClientWarpSource& src, uint32_t band, uint32_t bits, const SoftBandRequest* request) {
  const VisibilityBuffer& buffer = *input.buffer;
  const bool edges = band > 0 && bits != 0;
  if (!edges) band = bits = 0;
  const bool shares = request != nullptr && request->layout != nullptr && request->bits != 0;
  if (shares && request->pass == nullptr) throw std::invalid_argument("WarpSourceBuffers::upload: shares without a pass");
  const uint32_t refine_bits = shares ? request->bits : 0u;
  const VkDeviceSize mask_bytes = (buffer.size_bytes() + 3) / 4 * 4;
  const VkDeviceSize share_offset = edges ? 2 * mask_bytes : mask_bytes;
  if (input.key == 0 || input.key != key || band != edge_band || bits != edge_bits || refine_bits != share_bits) {
    if (shares) share_shape = soft_band_shape(buffer.width, buffer.height, soft_band_radius(buffer.width));
    const VkDeviceSize bytes = share_offset + (shares ? SoftBandPass::table_words(share_shape) * 4 : 0);
    if (bytes > visibility.size()) visibility = vk::Buffer(context, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, kHost);
    visibility.write(buffer.data.data(), buffer.data.size());
    if (edges) {
      const VisibilityBuffer marks = edge_band_marks(buffer, input.row_valid, band, bits);
      visibility.write(marks.data.data(), marks.data.size(), mask_bytes);
    }
    key = input.key;
    edge_band = band;
    edge_bits = bits;
    share_bits = refine_bits;
  }
  if (shares) {
    // Recorded with every upload, also of a buffer held already: a table whose command buffer was recorded but not
    // submitted (an error later in the frame) is never relied on.
    SoftBandSource source;
    source.visibility = &visibility;
    source.rows = &rows;
    source.has_rows = !input.row_valid.empty();
    source.width = buffer.width;
    source.height = buffer.height;
    source.mask_bits = static_cast<uint32_t>(buffer.mask_bits);
    source.share_word = static_cast<uint32_t>(share_offset / 4);
    request->pass->record(request->cmd, request->use, source, *request->layout, refine_bits,
                          soft_band_radius(buffer.width));
    src.share_word = static_cast<uint32_t>(share_offset / 4);
    src.share_cell_shift = static_cast<uint32_t>(std::countr_zero(share_shape.cell));
    src.share_columns = share_shape.columns;
    src.flags |= kClientSourceHasShares;
  }
  if (edges) {
    src.edge_word = static_cast<uint32_t>(mask_bytes / 4);
    src.flags |= kClientSourceHasEdges;
  }
  src.mask_bits = static_cast<uint32_t>(buffer.mask_bits);
  src.flags |= kClientSourceHasVisibility;
  if (same_eye(display, input.traced)) src.flags |= kClientSourceSameEye;
  if (!input.row_valid.empty()) {
    std::array<uint32_t, kRowWords> words{};
    for (size_t r = 0; r < input.row_valid.size(); ++r) {
      if (input.row_valid[r] != 0) words[r / 32] |= 1u << (r % 32);
    }
    rows.write(words.data(), words.size() * 4);
    src.flags |= kClientSourceHasRowValidity;
  }
}

}  // namespace dhr::render
