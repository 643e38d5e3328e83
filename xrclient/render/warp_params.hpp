// The warp's GPU parameters (shader_interface.h's ClientWarpParams) from cameras, visibility inputs and shadow
// maps, and the host-visible buffers a visibility source is uploaded into. Shared by the compute warp
// (warp_pass) and the forward pass (forward_pass), which apply the same rule.
#pragma once
#include <array>
#include <cstdint>
#include <span>

#include "math/projection.hpp"
#include "plan/visibility_input.hpp"
#include "render/soft_band_pass.hpp"
#include "render/warp_reference.hpp"
#include "scene/scene.hpp"
#include "shaders/shader_interface.h"
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"
#include "vk/buffer.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

class ShadowMaps;

// A source's parameters, computed in double: everything is relative to the new eye, so only small numbers
// reach the GPU. `traced` is null without a usable visibility buffer.
shader::ClientWarpSource make_warp_source(const Camera& display, const Camera* traced);
// Display-level parameters (the sources are the caller's).
shader::ClientWarpParams make_warp_params(const Camera& display, const Camera* traced, double near_plane);

// The shadow-map fields of `params` (light count, biases, sizes) and the lights relative to the display eye:
// `shadow_lights` (ClientShadowLight[lights.size()]) and `packed` (PackedLight[lights.size()]). Throws
// std::invalid_argument when the lights differ from the maps' or exceed kMaxLights.
void describe_shadow_maps(const ShadowMaps& maps, std::span<const SceneLight> lights, const Camera& display,
                          shader::ClientWarpParams& params, std::array<shader::ClientShadowLight, kMaxLights>& shadow_lights);

// The warp's per-pixel counts on the GPU (warp.comp, status_count.comp): kClientCountWords words of three
// 10-bit fields per bucket of kClientCountBucketGroups workgroups; how many words a display size needs, and
// their sum as WarpCounts (read from a host-visible buffer after the GPU finished).
uint32_t warp_count_words(Extent extent);
WarpCounts unpack_warp_counts(const vk::Buffer& counters, uint32_t words);

// A visibility source on the GPU: its packed masks and row validity in host-visible storage buffers.
struct WarpSourceBuffers {
  static constexpr uint32_t kRowWords = kMaxBufferDimension / 32;
  vk::Buffer visibility;  // grown on demand
  vk::Buffer rows;        // kRowWords words
  uint64_t key = 0;       // VisibilityInput::key of what `visibility` holds (0: always upload)
  uint32_t edge_band = 0;  // the edge band and bits the held marks were computed with
  uint32_t edge_bits = 0;
  uint32_t share_bits = 0;  // the refined fields the held band shares were made for
  SoftBandShape share_shape;  // the held band shares' cells (the table follows the masks)

  explicit WarpSourceBuffers(const vk::Context& context);
  // Uploads a validated input (skipping it when its key, band and bits are the ones held) and fills `src`: mask
  // width, kClientSourceHasVisibility, kClientSourceSameEye, kClientSourceHasRowValidity with the rows uploaded.
  // edge_band > 0 and edge_bits != 0: the edge band's marks of those bits (render/warp_edges.hpp) follow the masks,
  // from src.edge_word on, with kClientSourceHasEdges. `shares` with a layout and bits != 0: the band shares of
  // those fields (render/soft_bands.hpp) follow, from src.share_word on, with kClientSourceHasShares: the pass that
  // makes them is recorded into shares->cmd with every upload (the rows are read when it runs).
  void upload(const vk::Context& context, const Camera& display, const VisibilityInput& input,
              shader::ClientWarpSource& src, uint32_t edge_band = 0, uint32_t edge_bits = 0,
              const SoftBandRequest* shares = nullptr);
};

}  // namespace dhr::render
