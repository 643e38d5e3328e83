// The per-eye visibility pipeline, into this eye's own images, recorded into a command buffer the caller owns
// and submits, with GPU timestamps around each pass. Two paths apply the same rule:
//   forward  (the default whenever it can: the paper's warp or WarpSettings::server_edges() with or without the
//            depth test, the shaded view, no motion vectors): one raster pass that warps and shades each fragment (forward_pass.hpp) plus a
//            small count pass;
//   deferred (any other warp setting or debug view): G-buffer -> warp -> shading.
// With the warp's depth test on, prepare() first renders the depth of the camera this eye's newest
// visibility was traced for, at 1 / WarpSettings::depth_scale of its resolution (depth_camera; once per traced
// camera; the previous one is kept for the previous buffer, the warp's source 2); the other eye's pipeline reads the
// newest as its source 1. With WarpSettings::depth_splat it makes that depth from this eye's previous display frame
// instead of rendering it (traced_depth_splat.hpp).
//
// Frames in flight: host-written per-frame resources (visibility upload, lights, counters, timestamps) exist
// once per slot; the caller records frame n with slot n % frames_in_flight after waiting for that slot's
// previous submission (its fence), and reads that frame's stats after the submission completed. Images are
// shared by all slots: recording order on one queue plus the passes' barriers keep them consistent.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "math/projection.hpp"
#include "render/forward_pass.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/warp_motion.hpp"
#include "render/warp_pass.hpp"
#include "render/render_camera.hpp"
#include "render/shading_pass.hpp"
#include "render/shadow_maps.hpp"
#include "render/traced_depth_splat.hpp"
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
  WarpSettings warp;              // the warp's ingredients (default: the paper's warp)
  ShadingSettings shading;
  bool forward = true;            // false: always the deferred passes
  // The forward path shades every fragment a pixel draws (overdraw) with the whole light loop, the deferred path
  // each pixel once: with many lights deferred is cheaper (bench/client_bench: from 8-16 lights on lavapipe).
  uint32_t forward_max_lights = 8;
  bool forward_mask = false;      // the forward path also writes the mask (mask(): dhr-eval, tests)
};

struct EyePassTimes {
  bool valid = false;  // false without timestamp support or before the slot's first frame
  double traced_depth_ms = 0.0;  // prepare(): the traced camera's depth (0 when nothing was rendered)
  double gbuffer_ms = 0.0;
  double warp_ms = 0.0;
  double shading_ms = 0.0;
  double forward_ms = 0.0;  // the forward path's raster-and-shade pass and its count pass (0 on the deferred path)
  double total_ms = 0.0;
  // The frame's shadow-map re-render (client::StereoPipeline records it once per frame, before both eyes; eye 0
  // carries it, not in total_ms): 0 when nothing was re-rendered.
  double shadow_update_ms = 0.0;
};

struct EyeStats {
  Extent extent;
  EyePassTimes gpu;
  WarpCounts warp;              // per-status pixel counts of the warp
  GBufferDrawStats draws;
  bool visibility_used = false;  // a usable visibility buffer was given
  bool traced_depth_rendered = false;  // prepare() rendered a traced camera's depth this frame
  bool forward = false;                // the frame took the forward path
  ShadowUpdate shadow_update;          // eye 0: the frame's re-rendered shadow maps (see shadow_update_ms)
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

  // With the depth test on: renders the depth of visibility.traced, and of older->traced (this eye's
  // previous buffer, with WarpSettings::older_buffer), unless it is held (the two cameras rendered last;
  // nothing without a buffer). Call for both eyes before recording either (record reads the other's).
  void prepare(VkCommandBuffer cmd, uint32_t slot, const VisibilityInput& visibility,
               const VisibilityInput* older = nullptr);
  // The depth prepare() rendered, when one of the two held was rendered for `traced` (with
  // depth_camera(traced, warp_settings().depth_scale)); null otherwise.
  vk::Image* traced_depth(const Camera& traced);

  // Records the three passes for `view` (the display camera is the view's FOV over extent(), no guard band)
  // and the newest visibility of this eye (source 0); `other` is the other eye's (source 1, used with
  // WarpSettings::other_eye), `shadow_maps` the client's (required by the shadow settings) and `older` this
  // eye's previous visibility (source 2, used with WarpSettings::older_buffer; its traced depth is this
  // pipeline's, from prepare()); `moved` the scene at the frame's scene time (null: at rest; its lights shade).
  // Afterwards
  // output() is in GENERAL layout with its writes visible to later transfers and shaders (the frame sink
  // copies it from there).
  // With WarpSettings::motion and a moving scene, each source's bits that something moved since its scene time
  // (VisibilityInput::scene_time_ns) may have changed are unknown (warp_motion.hpp).
  void record(VkCommandBuffer cmd, uint32_t slot, const View& view, const VisibilityInput& visibility,
              const WarpSourceInput& other = {}, const ShadowMaps* shadow_maps = nullptr,
              const VisibilityInput* older = nullptr, const MovedScene* moved = nullptr);

  // Stats of the frame last recorded with `slot`; call after its submission completed.
  EyeStats read_stats(uint32_t slot) const;

  Extent extent() const { return extent_; }
  uint32_t frames_in_flight() const { return options_.frames_in_flight; }
  ShadingSettings& shading() { return options_.shading; }
  WarpSettings& warp_settings() { return options_.warp; }
  const EyePipelineOptions& options() const { return options_; }

  // Whether record() takes the forward path with the current settings.
  bool uses_forward() const;
  // What the last record() wrote (for every slot: images are shared):
  vk::Image& output();  // R8G8B8A8_UNORM, sRGB-encoded bytes, GENERAL
  vk::Image& mask();    // R32_UINT light masks (the forward path's only with forward_mask; else a 1x1 placeholder)
  bool last_forward() const { return last_forward_; }  // the last record() took the forward path
  // The deferred path's images (created on its first use).
  GBuffer& gbuffer() { return gbuffer_; }
  WarpTargets& warp() { return warp_; }

 private:
  // The motion rule's parameters for this frame's sources, or null (rule off, or nothing moves).
  const shader::ClientWarpMotion* warp_motion(const Camera& display, std::span<const SceneLight> lights,
                                              const VisibilityInput& visibility, const WarpSourceInput& other,
                                              const VisibilityInput* older, const MovedScene* moved);
  struct Slot {
    vk::TimestampQueries timestamps;
    vk::TimestampQueries prepare_timestamps;
    bool traced_depth_rendered = false;
    GBufferDrawStats draws;
    bool visibility_used = false;
    bool recorded = false;
    bool forward = false;
  };
  void create_images();
  void ensure_deferred_images();

  const vk::Context* context_;
  const ClientScene* scene_;
  Extent extent_;
  EyePipelineOptions options_;
  GBufferPass gbuffer_pass_;
  WarpPass warp_pass_;
  ShadingPass shading_pass_;
  std::unique_ptr<ForwardPass> forward_pass_;  // with EyePipelineOptions::forward
  ForwardTargets forward_;
  bool deferred_images_ = false;
  bool last_forward_ = false;
  GBuffer gbuffer_;
  // Traced cameras' G-buffers (only their depth is read), the newest two rendered; empty until prepared.
  std::array<GBuffer, 2> traced_;
  std::array<std::optional<Camera>, 2> traced_camera_;  // what traced_ holds (depth cameras)
  std::array<bool, 2> traced_splat_{};                  // ... and whether it was splatted (depth_splat) or rendered
  size_t newest_ = 1;  // which of traced_ holds the newest camera rendered
  // WarpSettings::depth_splat: the traced depth from the previous display frame (made on first use).
  std::unique_ptr<TracedDepthSplat> splat_;
  std::optional<Camera> last_display_;          // the camera of the last frame record() recorded
  const vk::Image* last_display_depth_ = nullptr;  // its depth (forward_.depth or gbuffer_.depth)
  WarpTargets warp_;
  vk::Image output_;
  std::vector<Slot> slots_;
  // The warp's motion rule for the frame being recorded (copied into the slot's parameters while recording).
  shader::ClientWarpMotion warp_motion_{};
  std::vector<WorldBox> motion_boxes_;
  std::optional<VisibilityLayout> motion_layout_;  // the lights' fields for the motion rule
};

}  // namespace dhr::render
