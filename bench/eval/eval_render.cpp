#include "eval_render.hpp"

#include "render/offscreen_sink.hpp"
#include "vk/context.hpp"
#include "vk/image.hpp"

#include <algorithm>
#include <chrono>

namespace dhr::eval {

EyeRenderer::EyeRenderer(const vk::Context& context, const Scene& scene, Extent eye,
                         const render::ShadowMapSettings& shadow_maps, bool forward)
    : context_(&context), scene_(context, scene), shadow_settings_(shadow_maps),
      light_count_(static_cast<uint32_t>(std::min<size_t>(scene.lights.size(), kMaxLights))) {
  render::EyePipelineOptions options;
  options.frames_in_flight = 1;  // every frame is submitted and waited for
  // `dhr-eval run`: every method and the truth on the deferred path: one shading computation for all (the forward
  // path's colours differ by up to 2/255, which the image metrics would count against the methods that cannot use
  // it), so the metrics compare visibility only. The shipped client's cost is bench/client_bench's.
  options.forward = forward;
  options.forward_mask = true;  // render() reads the masks back
  for (auto& pipeline : eyes_) pipeline = std::make_unique<render::EyePipeline>(context, scene_, eye, options);
}

std::array<EyeRender, 2> EyeRenderer::render(const std::array<View, 2>& views,
                                             const std::array<VisibilityInput, 2>& inputs,
                                             const render::WarpSettings& settings,
                                             const std::array<VisibilityInput, 2>& older) {
  if (settings.uses_shadow_maps() && !shadow_maps_) {
    shadow_maps_ = std::make_unique<render::ShadowMaps>(*context_, scene_, shadow_settings_);
  }
  std::array<EyeRender, 2> out;
  const auto start = std::chrono::steady_clock::now();
  context_->submit_and_wait([&](VkCommandBuffer cmd) {
    for (size_t e = 0; e < 2; ++e) {
      eyes_[e]->warp_settings() = settings;
      eyes_[e]->prepare(cmd, 0, inputs[e], &older[e]);
    }
    for (size_t e = 0; e < 2; ++e) {
      const VisibilityInput& other = inputs[1 - e];
      render::WarpSourceInput source;
      source.visibility = &other;
      if (other.buffer != nullptr) source.traced_depth = eyes_[1 - e]->traced_depth(other.traced);
      eyes_[e]->record(cmd, 0, views[e], inputs[e], source, shadow_maps_.get(), &older[e]);
    }
  });
  const double host_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / 2.0;
  for (size_t e = 0; e < 2; ++e) {
    render::EyePipeline& pipeline = *eyes_[e];
    EyeRender& r = out[e];
    r.host_ms = host_ms;
    r.stats = pipeline.read_stats(0);
    r.rgba = render::read_rgba8(*context_, pipeline.output());
    const Extent extent = pipeline.extent();
    std::vector<uint32_t> masks(static_cast<size_t>(extent.width) * extent.height);
    vk::read_image(*context_, pipeline.mask(), masks.data(), masks.size() * sizeof(uint32_t));
    r.mask = VisibilityBuffer::create(extent.width, extent.height, light_count_);
    const uint32_t bits = r.mask.light_bits();
    for (size_t p = 0; p < masks.size(); ++p) r.mask.set_mask_at(p, masks[p] & bits);
  }
  return out;
}

}  // namespace dhr::eval
