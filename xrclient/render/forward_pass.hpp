// Forward pass, graphics, one eye: rasterizes the ClientScene and shades every fragment in the same pass
// (shaders/client/forward_body.h): the G-buffer pass's materials, a light mask by mode, the shading pass's equation and display
// encoding. No G-buffer, no warp or shading dispatch, no full-screen intermediate images:
//   kLambert     every light, no shadows: what shading costs without shadows
//   kShadowMaps  the client's cube shadow maps (shadow_maps.hpp): what a headset would do without DHR
//   kPaperWarp   the paper's warp of this eye's newest visibility (the DHR client): the same decisions as the
//                compute warp (warp_pass) and its CPU reference, because the fragment's surface point comes from
//                gl_FragCoord exactly as the compute passes get it from the depth image. It also writes each
//                pixel's status into an R32_UINT attachment, which a small compute pass (status_count.comp)
//                sums into WarpCounts.
//   kServerEdges the warp with WarpSettings::server_edges(): source 0's 2x2 bilinear samples, bits they
//                disagree on and pixels without a sample from the client's shadow maps (looked up only there),
//                the compute warp's decisions (shaders/client/bilinear_warp.h); writes and counts the status as
//                kPaperWarp does, plus the shadow-map fills and edges. With a traced depth
//                (ForwardFrame::traced_depth) samples off the pixel's tangent plane are not used, as the compute
//                warp's depth test (WarpSettings::server_edges_depth).
// Targets, display-sized:
//   depth  D32_SFLOAT (reversed-Z, as the G-buffer's)
//   colour R8G8B8A8_UNORM, sRGB-encoded bytes (as the shading pass's output), ends in GENERAL
//   status R8_UINT  kClientStatus* | kClientForwardStatusShadow* (kPaperWarp, kServerEdges or write_mask; background where nothing was drawn; known
//                   everywhere drawn for the other modes), else a 1x1 placeholder
//   mask   R32_UINT light mask (ForwardOptions::write_mask: tests; background: the unknown mask), else 1x1
// Each pipeline has exactly the attachments it writes (shaders/client/forward*.frag share forward_body.h).
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <vector>

#include "math/projection.hpp"
#include "plan/visibility_input.hpp"
#include "render/pass_util.hpp"
#include "render/render_camera.hpp"
#include "render/scene_draw.hpp"
#include "render/shading_pass.hpp"
#include "render/warp_params.hpp"
#include "render/warp_reference.hpp"
#include "scene/scene.hpp"
#include "vk/buffer.hpp"
#include "vk/handle.hpp"
#include "vk/image.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

class ClientScene;
class ShadowMaps;

// Values equal shader_interface.h's kClientForward* constants.
enum class ForwardMode : uint32_t { kLambert = 0, kShadowMaps = 1, kPaperWarp = 2, kServerEdges = 3 };
// Whether the mode writes and counts the status (the warp modes).
bool counts_status(ForwardMode mode);
const char* to_string(ForwardMode mode);

struct ForwardOptions {
  ForwardMode mode = ForwardMode::kPaperWarp;
  bool write_mask = false;  // the mask attachment (tests)
  uint32_t slots = 1;       // host-written resources per frame in flight
};

struct ForwardTargets {
  vk::Image depth;
  vk::Image colour;
  vk::Image status;
  vk::Image mask;

  static ForwardTargets create(const vk::Context& context, Extent extent, const ForwardOptions& options);
  Extent extent() const { return Extent{colour.width(), colour.height()}; }
  bool has_status() const { return status.width() == colour.width() && status.height() == colour.height(); }
  bool has_mask() const { return mask.width() == colour.width() && mask.height() == colour.height(); }
};

struct ForwardFrame {
  Camera display;
  double near_plane = kDefaultNearPlane;
  const VisibilityInput* visibility = nullptr;  // the warp modes: this eye's newest (null: none, all unknown)
  const ShadowMaps* shadow_maps = nullptr;      // kShadowMaps, kServerEdges (required)
  std::span<const SceneLight> lights;           // the scene's lights at the frame's time (at most kMaxLights)
  const MovedScene* moved = nullptr;            // the scene at the frame's scene time (null: at rest)
  ShadingSettings shading;                      // exposure, background, swap_red_blue; view must be kShaded
  // kServerEdges: source 0's traced depth, rendered with depth_camera(traced, depth_test.depth_scale), in
  // SHADER_READ_ONLY_OPTIMAL; null: no depth test. depth_test: its depth_scale and plane tolerances.
  const vk::Image* traced_depth = nullptr;
  WarpSettings depth_test = WarpSettings::server_edges_depth(1);
  // kServerEdges: WarpSettings::edge_band (0: the 2x2 samples alone), server_edges()'s unless set.
  uint32_t edge_band = client::shipped::kEdgeBand;
  // kServerEdges: soft fields shade with their refined shares (WarpSettings::soft_refine).
  bool soft_refine = false;
  // kServerEdges: what moved (warp_motion.hpp), source 0's entry; null: nothing (WarpSettings::motion's rule off).
  const shader::ClientWarpMotion* motion = nullptr;
};

class ForwardPass {
 public:
  // Keeps a reference to the scene: it must outlive the pass.
  ForwardPass(const vk::Context& context, const ClientScene& scene, const ForwardOptions& options = {});

  // Writes the slot's buffers (the GPU must have finished the slot's previous use) and records the pass (and,
  // for kPaperWarp, the count pass). An unusable visibility input is logged and treated as none; the return
  // value's `visibility_used` says whether it was used. Throws std::invalid_argument for mismatched sizes, a bad
  // slot, more than kMaxLights lights (with light slots: a mode other than kLambert), a debug view, or
  // kShadowMaps without maps.
  struct Recorded {
    GBufferDrawStats draws;
    bool visibility_used = false;
  };
  Recorded record(VkCommandBuffer cmd, uint32_t slot, const ForwardFrame& frame, ForwardTargets& targets);

  // The warp modes: the per-status pixel counts of the slot's last recorded pass; call after its submission
  // completed.
  WarpCounts read_counts(uint32_t slot) const;
  const ForwardOptions& options() const { return options_; }
  // Switches the mode for the passes recorded after: only between modes with the same attachments (the
  // pipelines are made for them), else throws std::invalid_argument.
  void set_mode(ForwardMode mode);

 private:
  struct Slot {
    WarpSourceBuffers source;
    vk::Buffer params;         // ClientWarpParams
    vk::Buffer moved;          // ClientWarpMotion
    vk::Buffer shadow_lights;  // ClientShadowLight[kMaxLights]
    vk::Buffer lights;         // PackedLight[]: kMaxLights, or the scene's lights with light slots
    vk::Buffer shading;        // ClientForwardShading
    vk::Buffer counters;       // the warp modes: packed per-bucket counts, grown on demand
    uint32_t count_words = 0;
    bool counted = false;      // the last recorded pass counted
    VkDescriptorSet set = VK_NULL_HANDLE;
    VkDescriptorSet count_set = VK_NULL_HANDLE;
    Slot(const vk::Context& context, size_t max_lights);
  };

  const vk::Context* context_;
  const ClientScene* scene_;
  ForwardOptions options_;
  MaterialSets materials_;
  vk::DescriptorSetLayout frame_layout_;
  vk::DescriptorPool frame_pool_;
  vk::PipelineLayout layout_;
  vk::Pipeline cull_back_;
  vk::Pipeline cull_none_;
  vk::Sampler sampler_;
  ComputePassCore count_;
  SoftBandPass bands_;  // the source's band shares (use: the slot)
  vk::Image placeholder_atlas_;  // 1x1 D32 bound without shadow maps, and as the traced depth without one
  vk::Buffer light_slot_table_;  // LightSlots::gpu_words of the scene (a header alone without slots)
  std::vector<Slot> slots_;
};

}  // namespace dhr::render
