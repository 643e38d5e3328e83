// Both eyes' passes of one frame (a render::EyePipeline per eye) and the client's shadow maps. The eyes are
// recorded together because each eye's warp reads the other eye's newest visibility (source 1, with the traced
// depth the other eye's pipeline rendered) besides its own newest (source 0) and previous (source 2) one.
// The client's frame step (frame_step.hpp) records its frames with it; dhr-eval records its exact frames with
// it too, and shares one between its settings (their frame steps then leave the upload keys 0: a key names a
// frame of one client's stream; the traced depths held are found by their camera, so any owner may reuse them).
// A scene that moves is drawn at the frame's scene time (StereoInputs::scene_time_ns) by every pass, its lights
// moved too, and the shadow maps' stale faces are re-rendered first in the same command buffer (timed).
#pragma once
#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "math/projection.hpp"
#include "plan/visibility_input.hpp"
#include "render/eye_pipeline.hpp"
#include "render/client_motion.hpp"
#include "render/shadow_maps.hpp"
#include "vk/timestamps.hpp"

namespace dhr::vk {
class Context;
}
namespace dhr::render {
class ClientScene;
}

namespace dhr::client {

// What both eyes render in one frame.
struct StereoInputs {
  std::array<View, 2> views{};                // the display views
  std::array<VisibilityInput, 2> visibility;  // per eye, its newest (buffer null: none)
  std::array<VisibilityInput, 2> older;       // per eye, its previous one (buffer null: none)
  int64_t scene_time_ns = 0;                  // the scene time of the frame's display (FramePose::scene_time_ns)
  const NodeOverrides* node_overrides = nullptr;  // app-moved nodes (scene/node_overrides.hpp); null: none
  // Whose shadow maps: in a moving scene each owner's maps are re-rendered by its own frames (which faces, and
  // when, depend on what its frames show: record()). dhr-eval's settings each pass their own; a client has one.
  // A static scene's maps never change: every owner shares one.
  uint32_t shadow_owner = 0;
};

class StereoPipeline {
 public:
  // Keeps references to the context and the scene: they must outlive it. Renders the shadow maps now when
  // options.warp needs them (else on the first frame whose warp settings do).
  StereoPipeline(const vk::Context& context, const render::ClientScene& scene, Extent eye_extent,
                 const render::EyePipelineOptions& options, const render::ShadowMapSettings& shadow_maps = {});
  ~StereoPipeline();
  StereoPipeline(const StereoPipeline&) = delete;
  StereoPipeline& operator=(const StereoPipeline&) = delete;

  // Uploads and prepares both eyes (EyePipeline::prepare), then records each eye's passes (EyePipeline::record).
  // The shadow maps, when the warp settings need them and none were rendered yet, are rendered first (their
  // own submission, waited for; `cmd` may be recording meanwhile). In a moving scene, the scene is sampled at
  // inputs.scene_time_ns and the shadow maps' stale faces are re-rendered into `cmd` before the eyes: all of them
  // when an eye has no visibility or shows it at another scene time than it was traced for (the maps then shade
  // what moved), else each light's in its turn (ShadowMapSettings::fill_period_ns: the maps only fill).
  void record(VkCommandBuffer cmd, uint32_t slot, const StereoInputs& inputs);
  // Stats of both eyes' frame last recorded with `slot`; call after its submission completed. Eye 0 carries the
  // frame's shadow-map re-render (EyeStats::shadow_update, EyePassTimes::shadow_update_ms).
  std::array<render::EyeStats, 2> read_stats(uint32_t slot) const;

  // The eyes share one set of warp settings; a change applies from the next record().
  void set_warp_settings(const render::WarpSettings& settings);
  render::EyePipeline& eye(uint32_t index) { return *eyes_[index]; }
  const render::EyePipeline& eye(uint32_t index) const { return *eyes_[index]; }
  Extent extent() const { return eyes_[0]->extent(); }
  uint32_t frames_in_flight() const { return eyes_[0]->frames_in_flight(); }
  // Owner 0's (StereoInputs::shadow_owner); null until a warp setting needs them.
  const render::ShadowMaps* shadow_maps() const { return shadow_maps_.empty() ? nullptr : shadow_maps_[0].get(); }
  // The scene as the last record() drew it (unsampled for a static scene).
  const render::MovedScene& moved_scene() const { return moved_; }

 private:
  // The maps `owner`'s frames use (every owner's are owner 0's in a static scene); made when first needed, null
  // while the warp settings need none.
  render::ShadowMaps* ensure_shadow_maps(uint32_t owner);

  const vk::Context* context_;
  const render::ClientScene* scene_;
  std::array<std::unique_ptr<render::EyePipeline>, 2> eyes_;
  render::ShadowMapSettings shadow_settings_;
  std::vector<std::unique_ptr<render::ShadowMaps>> shadow_maps_;  // per owner
  render::MovedScene moved_;
  struct ShadowSlot {
    vk::TimestampQueries timestamps;  // around the frame's shadow-map re-render
    render::ShadowUpdate update;
    bool stamped = false;  // its timestamps were written (read_ns would wait for them otherwise)
  };
  std::vector<ShadowSlot> shadow_slots_;
};

}  // namespace dhr::client
