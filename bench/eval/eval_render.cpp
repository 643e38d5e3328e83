#include "eval_render.hpp"

#include "render/offscreen_sink.hpp"
#include "vk/context.hpp"
#include "vk/image.hpp"

#include <algorithm>
#include <chrono>

namespace dhr::eval {

EyeRenderer::EyeRenderer(const vk::Context& context, const Scene& scene, Extent eye)
    : context_(&context), scene_(context, scene),
      light_count_(static_cast<uint32_t>(std::min<size_t>(scene.lights.size(), kMaxLights))) {
  render::EyePipelineOptions options;
  options.frames_in_flight = 1;  // every frame is submitted and waited for
  for (auto& pipeline : eyes_) pipeline = std::make_unique<render::EyePipeline>(context, scene_, eye, options);
}

EyeRender EyeRenderer::render(int eye, const View& view, const VisibilityInput& input) {
  render::EyePipeline& pipeline = *eyes_[static_cast<size_t>(eye)];
  EyeRender out;
  const auto start = std::chrono::steady_clock::now();
  context_->submit_and_wait([&](VkCommandBuffer cmd) { pipeline.record(cmd, 0, view, input); });
  out.host_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  out.stats = pipeline.read_stats(0);
  out.rgba = render::read_rgba8(*context_, pipeline.output());
  const Extent extent = pipeline.extent();
  std::vector<uint32_t> masks(static_cast<size_t>(extent.width) * extent.height);
  vk::read_image(*context_, pipeline.warp().mask, masks.data(), masks.size() * sizeof(uint32_t));
  out.mask = VisibilityBuffer::create(extent.width, extent.height, light_count_);
  const uint32_t bits = out.mask.light_bits();
  for (size_t p = 0; p < masks.size(); ++p) out.mask.set_mask_at(p, masks[p] & bits);
  return out;
}

}  // namespace dhr::eval
