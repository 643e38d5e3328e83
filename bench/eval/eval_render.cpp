#include "eval_render.hpp"

#include "render/offscreen_sink.hpp"
#include "vk/context.hpp"
#include "vk/image.hpp"

#include <algorithm>
#include "image/png_writer.hpp"
#include <cstdio>
#include <cstdlib>
#include <glm/gtc/packing.hpp>
#include "render/render_camera.hpp"
#include <chrono>

namespace dhr::eval {

EyeRenderer::EyeRenderer(const vk::Context& context, const Scene& scene, Extent eye,
                         const render::ShadowMapSettings& shadow_maps)
    : context_(&context), scene_(context, scene), shadow_settings_(shadow_maps),
      light_count_(static_cast<uint32_t>(std::min<size_t>(scene.lights.size(), kMaxLights))) {
  render::EyePipelineOptions options;
  options.frames_in_flight = 1;  // every frame is submitted and waited for
  for (auto& pipeline : eyes_) pipeline = std::make_unique<render::EyePipeline>(context, scene_, eye, options);
}

std::array<EyeRender, 2> EyeRenderer::render(const std::array<View, 2>& views,
                                             const std::array<VisibilityInput, 2>& inputs,
                                             const render::WarpSettings& settings) {
  if (settings.uses_shadow_maps() && !shadow_maps_) {
    shadow_maps_ = std::make_unique<render::ShadowMaps>(*context_, scene_, shadow_settings_);
    if (std::getenv("DHR_EVAL_PROBE") != nullptr) {
      vk::Image& atlas = shadow_maps_->atlas();
      std::vector<float> d(size_t{atlas.width()} * atlas.height());
      vk::read_image(*context_, atlas, d.data(), d.size() * 4);
      std::vector<uint8_t> g(d.size());
      for (size_t i = 0; i < d.size(); ++i) {
        const double z = d[i] > 0.0f ? shadow_settings_.near_plane / double(d[i]) : 10.0;
        g[i] = static_cast<uint8_t>(std::clamp(z / 6.0 * 255.0, 0.0, 255.0));
      }
      write_png("/tmp/atlas.png", atlas.width(), atlas.height(), 1, g);
      const glm::dvec3 p(2.527, 1.113, -2.0);
      for (size_t l = 0; l < shadow_maps_->tiles().size(); ++l) {
        const render::ShadowTile& t = shadow_maps_->tiles()[l];
        const render::CubeLookup c = render::cube_lookup(p - t.position, shadow_maps_->face_size());
        const size_t S = shadow_maps_->face_size();
        const float v = d[(*t.row * S + size_t(c.texel.y)) * 6 * S + c.face * S + size_t(c.texel.x)];
        std::fprintf(stderr, "light %zu face %u texel %d,%d distance %.3f occluder %.3f\n", l, c.face, c.texel.x,
                     c.texel.y, c.distance, shadow_settings_.near_plane / double(v));
      }
    }
  }
  std::array<EyeRender, 2> out;
  const auto start = std::chrono::steady_clock::now();
  context_->submit_and_wait([&](VkCommandBuffer cmd) {
    for (size_t e = 0; e < 2; ++e) {
      eyes_[e]->warp_settings() = settings;
      eyes_[e]->prepare(cmd, 0, inputs[e]);
    }
    for (size_t e = 0; e < 2; ++e) {
      const VisibilityInput& other = inputs[1 - e];
      render::WarpSourceInput source;
      source.visibility = &other;
      if (other.buffer != nullptr) source.traced_depth = eyes_[1 - e]->traced_depth(other.traced);
      eyes_[e]->record(cmd, 0, views[e], inputs[e], source, shadow_maps_.get());
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
    vk::read_image(*context_, pipeline.warp().mask, masks.data(), masks.size() * sizeof(uint32_t));
    r.mask = VisibilityBuffer::create(extent.width, extent.height, light_count_);
    const uint32_t bits = r.mask.light_bits();
    for (size_t p = 0; p < masks.size(); ++p) r.mask.set_mask_at(p, masks[p] & bits);
    if (std::getenv("DHR_EVAL_PROBE") != nullptr) {
      std::vector<float> depth(masks.size());
      vk::read_image(*context_, pipeline.gbuffer().depth, depth.data(), depth.size() * 4);
      std::vector<uint16_t> normal(masks.size() * 4);
      vk::read_image(*context_, pipeline.gbuffer().normal, normal.data(), normal.size() * 2);
      const Camera cam = render::display_camera(views[e], extent);
      for (uint32_t x : {100u, 150u}) {
        const size_t i = 60 * extent.width + x;
        const glm::dvec3 w = render::world_point_from_depth(cam, 0.05, x + 0.5, 60.5, depth[i]);
        std::fprintf(stderr, "eye %zu px %u,60 eye (%.3f %.3f %.3f) world (%.3f %.3f %.3f) normal (%.3f %.3f %.3f) mask %u\n", e, x,
                     cam.T_world_eye.position.x, cam.T_world_eye.position.y, cam.T_world_eye.position.z, w.x, w.y, w.z,
                     double(glm::unpackHalf1x16(normal[i * 4])), double(glm::unpackHalf1x16(normal[i * 4 + 1])),
                     double(glm::unpackHalf1x16(normal[i * 4 + 2])), masks[i]);
      }
    }
  }
  return out;
}

}  // namespace dhr::eval
