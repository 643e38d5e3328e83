// Warp pass, compute, one eye: for every display pixel, the light mask of the newest visibility
// buffer looked up where the pixel's surface point lands in the old guard-banded camera it was traced for.
// The decision rule and its CPU reference: warp_reference.hpp. Outputs, all display-sized:
//   mask   R32_UINT   predicted light mask (all light bits where unknown)
//   status R32_UINT   (optional: debug views, tests) WarpStatus per pixel (kClientStatus* in shader_interface.h)
//   motion R32G32_SFLOAT (optional, debug) old-buffer lookup minus the lookup without any pose change, px
// plus per-status pixel counts (WarpCounts), summed per subgroup and atomically per bucket of workgroups.
// Optional outputs are 1x1 placeholders when off: each full-size store costs (about a sixth of the pass on
// lavapipe) and the frame loop only needs the mask and the counts.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <vector>

#include "math/projection.hpp"
#include "plan/visibility_input.hpp"
#include "visibility/visibility.hpp"
#include "render/warp_reference.hpp"
#include "render/pass_util.hpp"
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
};

struct WarpTargets {
  vk::Image mask;    // STORAGE | SAMPLED | TRANSFER_SRC
  vk::Image status;  // display-sized with status on, else a 1x1 placeholder
  vk::Image motion;  // display-sized with motion vectors on, else a 1x1 placeholder

  static WarpTargets create(const vk::Context& context, Extent extent, WarpOutputs outputs);
  Extent extent() const { return Extent{mask.width(), mask.height()}; }
  bool has_status() const { return status.width() == mask.width() && status.height() == mask.height(); }
  bool has_motion() const { return motion.width() == mask.width() && motion.height() == mask.height(); }
};

class WarpPass {
 public:
  // `slots`: host-written resources (visibility upload, row validity, counters, descriptor set) exist once
  // per slot so that several frames can be in flight.
  explicit WarpPass(const vk::Context& context, uint32_t slots = 1);

  // Writes the visibility into the slot's buffers (the GPU must have finished the slot's previous use)
  // and records the pass. `depth` (the G-buffer depth rendered with `display`) must be in
  // SHADER_READ_ONLY_OPTIMAL, as GBufferPass leaves it; the targets end in GENERAL with their writes visible
  // to later shaders and transfers. An unusable visibility input is logged and treated as no data; the
  // return value is false then. Throws std::invalid_argument for mismatched sizes or a bad slot.
  bool record(VkCommandBuffer cmd, uint32_t slot, vk::Image& depth, const Camera& display, double near_plane,
              const VisibilityInput& visibility, WarpTargets& targets);

  // The counts of the slot's last recorded pass; call after its submission completed.
  WarpCounts read_counts(uint32_t slot) const;
  uint32_t slots() const { return static_cast<uint32_t>(slots_.size()); }

 private:
  struct Slot {
    vk::Buffer visibility;  // host-visible storage buffer, grown on demand
    vk::Buffer rows;        // host-visible row-validity bitmask
    vk::Buffer counters;    // host-visible packed per-bucket counts, grown on demand
    uint32_t count_words = 0;  // words the last recorded pass counted into
    VkDescriptorSet set = VK_NULL_HANDLE;
    uint64_t key = 0;
  };
  void upload(Slot& slot, const VisibilityInput& visibility);

  const vk::Context* context_;
  ComputePassCore core_;
  std::vector<Slot> slots_;
};

}  // namespace dhr::render
