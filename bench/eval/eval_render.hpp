// The client's real eye pipelines (xrclient/frame/StereoPipeline: both eyes' G-buffer, prediction, shading),
// shared by every setting of a run, and their read-back: the shaded RGBA8 image and the predicted light masks.
// Settings render their frames through the client's own frame step (SettingSession: a FrameCoordinator over
// pipeline()); render() records exact frames (the ground truth) with the same pipelines.
#pragma once
#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"
#include "frame/stereo_pipeline.hpp"
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
  VisibilityBuffer mask;      // display-sized predicted masks in layout() (every light lit where unknown)
  // Per display pixel, the warp's refined soft shares (render/soft_refine.hpp) where the deferred warp wrote them;
  // empty otherwise (the soft fields shade with their levels).
  std::vector<uint32_t> soft;
  render::EyeStats stats;
  double host_ms = 0.0;       // record + submit + wait, host wall time
};

class EyeRenderer {
 public:
  // Throws (setup) when the scene cannot be uploaded. forward: take the client's forward path where it applies
  // (render::EyePipelineOptions::forward), to match pictures the client rendered that way; otherwise deferred.
  // The pipelines have one GPU slot: every frame is submitted and waited for.
  EyeRenderer(const vk::Context& context, const Scene& scene, Extent eye,
              const render::ShadowMapSettings& shadow_maps = {}, bool forward = false);
  // Renders both eyes with the paper's warp of the given buffers (the exact ones: at identity) and reads them back;
  // the scene as it is at scene_time_ns.
  std::array<EyeRender, 2> render(const std::array<View, 2>& views, const std::array<VisibilityInput, 2>& inputs,
                                  int64_t scene_time_ns);
  // What the last frame rendered with pipeline() wrote for `eye`: image and masks (stats and host_ms are left
  // for the caller, who submitted that frame).
  EyeRender read_back(uint32_t eye);
  client::StereoPipeline& pipeline() { return stereo_; }
  const vk::Context& context() const { return *context_; }
  // The masks' fields: the lights, or with more than kMaxLights lights the light slots they share
  // (ClientScene::field_lights).
  uint32_t light_count() const { return light_count_; }
  // The masks' layout (render::layout_for_lights of the field lights: a soft light's field holds its level).
  const VisibilityLayout& layout() const { return layout_; }

 private:
  const vk::Context* context_;
  render::ClientScene scene_;
  client::StereoPipeline stereo_;
  uint32_t light_count_ = 0;
  VisibilityLayout layout_;
};

}  // namespace dhr::eval
