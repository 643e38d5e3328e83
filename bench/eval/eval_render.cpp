#include "eval_render.hpp"

#include "render/light_layout.hpp"
#include "render/offscreen_sink.hpp"
#include "vk/context.hpp"
#include "vk/image.hpp"

#include <algorithm>
#include <chrono>

namespace dhr::eval {
namespace {

render::EyePipelineOptions pipeline_options(bool forward) {
  render::EyePipelineOptions options;
  options.frames_in_flight = 1;  // every frame is submitted and waited for
  // `dhr-eval run`: every method and the truth on the deferred path: one shading computation for all (the forward
  // path's colours differ by up to 2/255, which the image metrics would count against the methods that cannot use
  // it), so the metrics compare visibility only. The shipped client's cost is bench/client_bench's.
  options.forward = forward;
  options.forward_mask = true;  // read_back() reads the masks
  return options;
}

}  // namespace

EyeRenderer::EyeRenderer(const vk::Context& context, const Scene& scene, Extent eye,
                         const render::ShadowMapSettings& shadow_maps, bool forward)
    : context_(&context), scene_(context, scene), stereo_(context, scene_, eye, pipeline_options(forward), shadow_maps),
      light_count_(static_cast<uint32_t>(scene_.field_lights().size())),
      layout_(render::layout_for_lights(scene_.field_lights())) {}

std::array<EyeRender, 2> EyeRenderer::render(const std::array<View, 2>& views,
                                             const std::array<VisibilityInput, 2>& inputs, int64_t scene_time_ns) {
  stereo_.set_warp_settings(render::WarpSettings{});
  client::StereoInputs frame;
  frame.views = views;
  frame.visibility = inputs;
  frame.scene_time_ns = scene_time_ns;
  const auto start = std::chrono::steady_clock::now();
  context_->submit_and_wait([&](VkCommandBuffer cmd) { stereo_.record(cmd, 0, frame); });
  const double host_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / 2.0;
  const std::array<render::EyeStats, 2> stats = stereo_.read_stats(0);
  std::array<EyeRender, 2> out;
  for (uint32_t e = 0; e < 2; ++e) {
    out[e] = read_back(e);
    out[e].stats = stats[e];
    out[e].host_ms = host_ms;
  }
  return out;
}

EyeRender EyeRenderer::read_back(uint32_t eye) {
  render::EyePipeline& pipeline = stereo_.eye(eye);
  EyeRender r;
  r.rgba = render::read_rgba8(*context_, pipeline.output());
  const Extent extent = pipeline.extent();
  std::vector<uint32_t> masks(static_cast<size_t>(extent.width) * extent.height);
  vk::read_image(*context_, pipeline.mask(), masks.data(), masks.size() * sizeof(uint32_t));
  r.mask = VisibilityBuffer::create(extent.width, extent.height, layout_.total_bits());
  const uint32_t bits = r.mask.light_bits();
  for (size_t p = 0; p < masks.size(); ++p) r.mask.set_mask_at(p, masks[p] & bits);
  // The shares the soft fields were shaded with, where the warp refined them (the deferred path; the forward pass
  // shades with the same shares and has no target for them).
  render::WarpTargets& warp = pipeline.warp();
  if (!pipeline.last_forward() && warp.soft_written && warp.has_soft()) {
    r.soft.resize(masks.size());
    vk::read_image(*context_, warp.soft, r.soft.data(), r.soft.size() * sizeof(uint32_t));
  }
  return r;
}

}  // namespace dhr::eval
