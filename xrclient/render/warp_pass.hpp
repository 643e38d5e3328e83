// Warp pass, compute, one eye: for every display pixel, the light mask of the newest visibility buffer of this
// eye looked up where the pixel's surface point lands in the old guard-banded camera it was traced for, with
// the fills of WarpSettings (the other eye's buffer, this eye's previous buffer, neighbours on the pixel's
// tangent plane, the client's shadow maps). The decision rule and its CPU
// reference: warp_reference.hpp. Outputs, all display-sized:
//   mask   R32_UINT   predicted light mask (all light bits where unfilled)
//   status R32_UINT   (optional: debug views, tests) WarpStatus | WarpFill << 8 per pixel
//   motion R32G32_SFLOAT (optional, debug) old-buffer lookup minus the lookup without any pose change, px
//   soft   R32_UINT (optional: soft lights) refined soft shares, a byte per soft field (bilinear_warp.h)
// plus per-status and per-fill pixel counts (WarpCounts), summed per subgroup and atomically per bucket of
// workgroups. Optional outputs are 1x1 placeholders when off: each full-size store costs (about a sixth of
// the pass on lavapipe) and the frame loop only needs the mask and the counts.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <array>
#include <span>
#include <vector>

#include "math/projection.hpp"
#include "plan/visibility_input.hpp"
#include "scene/scene.hpp"
#include "visibility/visibility.hpp"
#include "render/warp_reference.hpp"
#include "render/pass_util.hpp"
#include "render/warp_params.hpp"
#include "vk/buffer.hpp"
#include "vk/handle.hpp"
#include "vk/image.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

// Which optional per-pixel outputs the warp writes.
struct WarpOutputs {
  bool status = false;  // WarpStatus per pixel
  bool motion = false;  // motion vectors
  bool soft = false;    // refined soft shares (a scene with soft lights; WarpSettings::soft_refine)
};

struct WarpTargets {
  vk::Image mask;    // STORAGE | SAMPLED | TRANSFER_SRC
  vk::Image status;  // display-sized with status on, else a 1x1 placeholder
  vk::Image motion;  // display-sized with motion vectors on, else a 1x1 placeholder
  vk::Image soft;    // display-sized with soft on, else a 1x1 placeholder: R32_UINT, warp_soft_blend's bytes
  bool soft_written = false;  // the last recorded warp wrote `soft` (the shading pass reads it then)

  static WarpTargets create(const vk::Context& context, Extent extent, WarpOutputs outputs);
  Extent extent() const { return Extent{mask.width(), mask.height()}; }
  bool has_status() const { return status.width() == mask.width() && status.height() == mask.height(); }
  bool has_motion() const { return motion.width() == mask.width() && motion.height() == mask.height(); }
  bool has_soft() const { return soft.width() == mask.width() && soft.height() == mask.height(); }
};

class ShadowMaps;

// One source of the warp: a visibility input and, for the depth test, the depth the client rendered for its
// traced camera (SHADER_READ_ONLY_OPTIMAL, the traced camera's extent; null: no depth test on this source).
struct WarpSourceInput {
  const VisibilityInput* visibility = nullptr;  // null: none
  vk::Image* traced_depth = nullptr;
};

// Everything one warp reads besides its targets.
struct WarpFrame {
  vk::Image* depth = nullptr;   // display G-buffer depth, SHADER_READ_ONLY_OPTIMAL (required)
  vk::Image* normal = nullptr;  // display G-buffer normal (required by the depth test and the shadow lookups)
  Camera display;
  double near_plane = kDefaultNearPlane;
  // This eye's newest, the other eye's (used with settings.other_eye), this eye's previous (settings.older_buffer).
  std::array<WarpSourceInput, 3> sources;
  const ShadowMaps* shadow_maps = nullptr;  // required by the shadow settings
  std::span<const SceneLight> lights;       // the scene's lights (shadow lookups)
  WarpSettings settings;
  const shader::ClientWarpMotion* motion = nullptr;  // settings.motion: what moved (warp_motion.hpp); null: nothing
};

class WarpPass {
 public:
  // `slots`: host-written resources (visibility uploads, row validity, parameters, counters, descriptor set)
  // exist once per slot so that several frames can be in flight.
  explicit WarpPass(const vk::Context& context, uint32_t slots = 1);

  // Writes the sources into the slot's buffers (the GPU must have finished the slot's previous use) and
  // records the pass. The targets end in GENERAL with their writes visible to later shaders and transfers.
  // An unusable visibility input is logged and treated as none; the return value is false when source 0's
  // was. Throws std::invalid_argument for mismatched sizes, a bad slot, or shadow settings without maps.
  bool record(VkCommandBuffer cmd, uint32_t slot, const WarpFrame& frame, WarpTargets& targets);

  // The counts of the slot's last recorded pass; call after its submission completed.
  WarpCounts read_counts(uint32_t slot) const;
  uint32_t slots() const { return static_cast<uint32_t>(slots_.size()); }

 private:
  struct Slot {
    std::vector<WarpSourceBuffers> sources;  // kClientWarpSourceCount
    vk::Buffer params;         // ClientWarpParams
    vk::Buffer moved;          // ClientWarpMotion
    vk::Buffer shadow_lights;  // ClientShadowLight[32]
    vk::Buffer lights;         // PackedLight[32]
    vk::Buffer counters;       // host-visible packed per-bucket counts, grown on demand
    uint32_t count_words = 0;  // words the last recorded pass counted into
    VkDescriptorSet set = VK_NULL_HANDLE;
  };

  const vk::Context* context_;
  ComputePassCore core_;
  SoftBandPass bands_;  // the sources' band shares (use: slot x kClientWarpSourceCount + source)
  vk::Image placeholder_depth_;   // 1x1 D32 for absent traced depths and shadow maps
  vk::Image placeholder_normal_;  // 1x1 RGBA16F for an absent normal image
  std::vector<Slot> slots_;
};
}  // namespace dhr::render
