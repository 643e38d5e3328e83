#include "frame/stereo_pipeline.hpp"

#include "log/log.hpp"
#include "render/client_scene.hpp"
#include "vk/context.hpp"

namespace dhr::client {

StereoPipeline::StereoPipeline(const vk::Context& context, const render::ClientScene& scene, Extent eye_extent,
                               const render::EyePipelineOptions& options,
                               const render::ShadowMapSettings& shadow_maps)
    : context_(&context), scene_(&scene), shadow_settings_(shadow_maps) {
  for (auto& eye : eyes_) eye = std::make_unique<render::EyePipeline>(context, scene, eye_extent, options);
  ensure_shadow_maps();
}

StereoPipeline::~StereoPipeline() = default;

void StereoPipeline::ensure_shadow_maps() {
  if (shadow_maps_ || !eyes_[0]->warp_settings().uses_shadow_maps()) return;
  shadow_maps_ = std::make_unique<render::ShadowMaps>(*context_, *scene_, shadow_settings_);
  log::info("shadow maps: %zu lights, %u texels per face, rendered in %.1f ms", shadow_maps_->tiles().size(),
            shadow_maps_->face_size(), shadow_maps_->render_ms());
}

void StereoPipeline::set_warp_settings(const render::WarpSettings& settings) {
  for (auto& eye : eyes_) eye->warp_settings() = settings;
}

void StereoPipeline::record(VkCommandBuffer cmd, uint32_t slot, const StereoInputs& inputs) {
  ensure_shadow_maps();
  // Both eyes' traced depths first: each eye's warp reads the other's as source 1.
  for (uint32_t e = 0; e < 2; ++e) eyes_[e]->prepare(cmd, slot, inputs.visibility[e], &inputs.older[e]);
  for (uint32_t e = 0; e < 2; ++e) {
    const VisibilityInput& other = inputs.visibility[1 - e];
    render::WarpSourceInput other_source;
    other_source.visibility = &other;
    if (other.buffer != nullptr) other_source.traced_depth = eyes_[1 - e]->traced_depth(other.traced);
    eyes_[e]->record(cmd, slot, inputs.views[e], inputs.visibility[e], other_source, shadow_maps_.get(),
                     &inputs.older[e]);
  }
}

std::array<render::EyeStats, 2> StereoPipeline::read_stats(uint32_t slot) const {
  return {eyes_[0]->read_stats(slot), eyes_[1]->read_stats(slot)};
}

}  // namespace dhr::client
