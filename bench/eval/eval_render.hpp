// The client's real per-eye pipeline (xrclient/render/EyePipeline: G-buffer, prediction, shading) run
// synchronously for one eye and read back: the shaded RGBA8 image and the predicted light masks.
#pragma once
#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "visibility/visibility.hpp"
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/shadow_maps.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dhr::vk {
class Context;
}

namespace dhr::eval {

struct EyeRender {
  std::vector<uint8_t> rgba;  // display-sized, sRGB-encoded bytes
  VisibilityBuffer mask;      // display-sized predicted masks (all light bits where unknown)
  render::EyeStats stats;
  double host_ms = 0.0;       // record + submit + wait, host wall time
};

class EyeRenderer {
 public:
  // Throws (setup) when the scene cannot be uploaded. forward: take the client's forward path where it applies
  // (render::EyePipelineOptions::forward), to match pictures the client rendered that way; otherwise deferred.
  EyeRenderer(const vk::Context& context, const Scene& scene, Extent eye,
              const render::ShadowMapSettings& shadow_maps = {}, bool forward = false);
  // Renders both eyes with the given warp settings (each eye's input is the other's source 1, `older` each
  // eye's previous buffer, source 2); shadow maps are rendered the first time settings need them.
  std::array<EyeRender, 2> render(const std::array<View, 2>& views, const std::array<VisibilityInput, 2>& inputs,
                                   const render::WarpSettings& settings = {},
                                   const std::array<VisibilityInput, 2>& older = {});
  uint32_t light_count() const { return light_count_; }

 private:
  const vk::Context* context_;
  render::ClientScene scene_;
  std::array<std::unique_ptr<render::EyePipeline>, 2> eyes_;
  render::ShadowMapSettings shadow_settings_;
  std::unique_ptr<render::ShadowMaps> shadow_maps_;
  uint32_t light_count_ = 0;
};

}  // namespace dhr::eval
