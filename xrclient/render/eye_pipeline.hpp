// The per-eye visibility pipeline: G-buffer -> warp -> shading, into this eye's own images,
// recorded into a command buffer the caller owns and submits. GPU timestamps around each pass.
//
// Frames in flight: host-written per-frame resources (visibility upload, lights, counters, timestamps) exist
// once per slot; the caller records frame n with slot n % frames_in_flight after waiting for that slot's
// previous submission (its fence), and reads that frame's stats after the submission completed. Images are
// shared by all slots: recording order on one queue plus the passes' barriers keep them consistent.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "math/projection.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/warp_pass.hpp"
#include "render/render_camera.hpp"
#include "render/shading_pass.hpp"
#include "vk/image.hpp"
#include "vk/timestamps.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

class ClientScene;

struct EyePipelineOptions {
  uint32_t frames_in_flight = 2;  // slots
  double near_plane = kDefaultNearPlane;
  bool motion_vectors = false;    // allocate and write the warp's motion vectors (debug)
  bool warp_status = false;       // allocate and write the warp's per-pixel status (debug, tests)
  ShadingSettings shading;
};

struct EyePassTimes {
  bool valid = false;  // false without timestamp support or before the slot's first frame
  double gbuffer_ms = 0.0;
  double warp_ms = 0.0;
  double shading_ms = 0.0;
  double total_ms = 0.0;
};

struct EyeStats {
  Extent extent;
  EyePassTimes gpu;
  WarpCounts warp;              // per-status pixel counts of the warp
  GBufferDrawStats draws;
  bool visibility_used = false;  // a usable visibility buffer was given
  uint64_t unknown_pixels() const { return warp.unknown_surface(); }
};

class EyePipeline {
 public:
  // Keeps a reference to the scene: it must outlive the pipeline. Throws std::invalid_argument for a
  // zero extent or zero slots.
  EyePipeline(const vk::Context& context, const ClientScene& scene, Extent extent,
              const EyePipelineOptions& options = {});
  ~EyePipeline();
  EyePipeline(const EyePipeline&) = delete;
  EyePipeline& operator=(const EyePipeline&) = delete;

  // Recreates the images for a new per-eye size (no-op when unchanged). Waits for the device to be idle
  // (vkDeviceWaitIdle): call it from the thread that submits, between frames.
  void resize(Extent extent);

  // Records the three passes for `view` (the display camera is the view's FOV over extent(), no guard band)
  // and the newest visibility of this eye. Afterwards output() is in GENERAL layout with its writes visible
  // to later transfers and shaders (the frame sink copies it from there).
  void record(VkCommandBuffer cmd, uint32_t slot, const View& view, const VisibilityInput& visibility);

  // Stats of the frame last recorded with `slot`; call after its submission completed.
  EyeStats read_stats(uint32_t slot) const;

  Extent extent() const { return extent_; }
  uint32_t frames_in_flight() const { return options_.frames_in_flight; }
  ShadingSettings& shading() { return options_.shading; }
  const EyePipelineOptions& options() const { return options_; }

  vk::Image& output() { return output_; }  // R8G8B8A8_UNORM, sRGB-encoded bytes
  GBuffer& gbuffer() { return gbuffer_; }
  WarpTargets& warp() { return warp_; }

 private:
  struct Slot {
    vk::TimestampQueries timestamps;
    GBufferDrawStats draws;
    bool visibility_used = false;
    bool recorded = false;
  };
  void create_images();

  const vk::Context* context_;
  const ClientScene* scene_;
  Extent extent_;
  EyePipelineOptions options_;
  GBufferPass gbuffer_pass_;
  WarpPass warp_pass_;
  ShadingPass shading_pass_;
  GBuffer gbuffer_;
  WarpTargets warp_;
  vk::Image output_;
  std::vector<Slot> slots_;
};

}  // namespace dhr::render
