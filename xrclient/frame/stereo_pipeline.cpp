#include "frame/stereo_pipeline.hpp"

#include "log/log.hpp"
#include "render/client_scene.hpp"
#include "vk/context.hpp"

namespace dhr::client {

StereoPipeline::StereoPipeline(const vk::Context& context, const render::ClientScene& scene, Extent eye_extent,
                               const render::EyePipelineOptions& options,
                               const render::ShadowMapSettings& shadow_maps)
    : context_(&context), scene_(&scene), shadow_settings_(shadow_maps) {
  render::EyePipelineOptions eye_options = options;
  if (!scene.light_slots().is_identity() && options.warp.uses_shadow_maps()) {
    // The client's shadow maps hold at most 32 lights: none for a scene whose lights share light slots.
    log::warn("%zu lights share light slots: no client shadow maps (undecided bits take the samples' vote, "
              "unfilled pixels are lit)", scene.lights().size());
    eye_options.warp = options.warp.without_shadow_maps();
  }
  for (auto& eye : eyes_) eye = std::make_unique<render::EyePipeline>(context, scene, eye_extent, eye_options);
  if (scene.motion().animated()) {
    shadow_slots_.resize(options.frames_in_flight);
    for (ShadowSlot& s : shadow_slots_) s.timestamps = vk::TimestampQueries(context, 2);
  }
  ensure_shadow_maps(0);
}

StereoPipeline::~StereoPipeline() = default;

render::ShadowMaps* StereoPipeline::ensure_shadow_maps(uint32_t owner) {
  if (!eyes_[0]->warp_settings().uses_shadow_maps()) return nullptr;
  if (!scene_->motion().animated()) owner = 0;
  if (owner >= shadow_maps_.size()) shadow_maps_.resize(size_t{owner} + 1);
  std::unique_ptr<render::ShadowMaps>& maps = shadow_maps_[owner];
  if (!maps) {
    maps = std::make_unique<render::ShadowMaps>(*context_, *scene_, shadow_settings_);
    log::info("shadow maps: %zu lights, %u texels per face, rendered in %.1f ms", maps->tiles().size(),
              maps->face_size(), maps->render_ms());
  }
  return maps.get();
}

void StereoPipeline::set_warp_settings(const render::WarpSettings& settings) {
  const bool slots = !scene_->light_slots().is_identity();
  for (auto& eye : eyes_) eye->warp_settings() = slots ? settings.without_shadow_maps() : settings;
}

void StereoPipeline::record(VkCommandBuffer cmd, uint32_t slot, const StereoInputs& inputs) {
  render::ShadowMaps* maps = ensure_shadow_maps(inputs.shadow_owner);
  const render::MovedScene* moved = nullptr;
  if (scene_->motion().animated()) {
    scene_->motion().sample(render::scene_seconds(inputs.scene_time_ns), scene_->meshes(), moved_,
                            inputs.node_overrides);
    moved = &moved_;
    ShadowSlot& s = shadow_slots_.at(slot);
    s.update = {};
    if (maps) {
      // The maps only fill while both eyes show visibility traced for the scene time shown; otherwise they shade
      // whatever moved since (the warp's motion rule), or everything (no visibility): every stale face now.
      bool fills_only = true;
      for (const VisibilityInput& v : inputs.visibility) {
        fills_only = fills_only && v.buffer != nullptr && v.scene_time_ns == inputs.scene_time_ns;
      }
      const render::ShadowRefresh refresh{inputs.scene_time_ns, shadow_settings_.fill_period_ns, !fills_only};
      s.timestamps.reset(cmd);
      s.timestamps.write(cmd, 0);
      s.update = maps->update(cmd, moved_, refresh);
      s.timestamps.write(cmd, 1);
      s.stamped = s.timestamps.supported();
    }
  }
  // Both eyes' traced depths first: each eye's warp reads the other's as source 1.
  for (uint32_t e = 0; e < 2; ++e) eyes_[e]->prepare(cmd, slot, inputs.visibility[e], &inputs.older[e]);
  for (uint32_t e = 0; e < 2; ++e) {
    const VisibilityInput& other = inputs.visibility[1 - e];
    render::WarpSourceInput other_source;
    other_source.visibility = &other;
    if (other.buffer != nullptr) other_source.traced_depth = eyes_[1 - e]->traced_depth(other.traced);
    eyes_[e]->record(cmd, slot, inputs.views[e], inputs.visibility[e], other_source, maps,
                     &inputs.older[e], moved);
  }
}

std::array<render::EyeStats, 2> StereoPipeline::read_stats(uint32_t slot) const {
  std::array<render::EyeStats, 2> stats = {eyes_[0]->read_stats(slot), eyes_[1]->read_stats(slot)};
  if (slot < shadow_slots_.size() && !shadow_maps_.empty() && stats[0].gpu.valid) {
    const ShadowSlot& s = shadow_slots_[slot];
    stats[0].shadow_update = s.update;
    const std::vector<double> ns = s.stamped ? s.timestamps.read_ns() : std::vector<double>{};
    if (ns.size() == 2 && s.update.faces > 0) stats[0].gpu.shadow_update_ms = (ns[1] - ns[0]) * 1e-6;
  }
  return stats;
}

}  // namespace dhr::client
