// The Embree backend of VisibilityTracer (CPU; also the reference for the Vulkan backend).
//
// Per eye: the image is cut into tiles handed to `threads` std::threads through an atomic counter; each
// pixel's result depends only on its own rays, so the output is identical for any thread count. Primary
// rays go through pixel centres (16-ray packets by default); each hit becomes a surface point rebuilt from
// the triangle's vertices; then one occlusion ray per light that can contribute (see light_eval.h), from
// an origin offset along the geometric normal (ray_offset.hpp). See docs/server.md.
#pragma once
#include "trace/embree/embree_scene.hpp"
#include "trace/embree/shadow_query.hpp"
#include "trace/soft/light_sampler.hpp"
#include "trace/soft/soft_visibility.hpp"
#include "trace/visibility_tracer.hpp"

#include <memory>

namespace dhr::server {

// Internal knobs, measured in docs/server.md; the defaults are the fastest found on this machine's kind.
struct EmbreeTracerConfig {
  EmbreeBuildOptions build;
  bool primary_packets = true;                  // rtcIntersect16 per 4x4 block (false: rtcIntersect1 per pixel)
  ShadowQuery shadow_query = ShadowQuery::kStream;
  uint32_t tile_size = 16;                      // pixels per tile side (a multiple of 4)
};

class EmbreeTracer final : public VisibilityTracer {
 public:
  // More than kMaxLights lights share slots (light_slots()). Throws std::runtime_error when the scene has more than
  // kMaxSlotLights lights, more than kMaxLights in a scene with animation, or Embree fails.
  EmbreeTracer(const Scene& scene, const TracerOptions& options, const EmbreeTracerConfig& config = {});
  ~EmbreeTracer() override;

  TracerBackend backend() const override { return TracerBackend::kEmbree; }
  std::string device_description() const override;
  const AccelStats& accel_stats() const override;
  uint32_t light_count() const override;
  const LightSlots* light_slots() const override;
  void trace(const Camera& camera, VisibilityBuffer& out, TraceStats& out_stats) override;
  void trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out, TraceStats& out_stats) override;
  std::vector<bool> light_extents() const override;
  // Soft fields: each soft light sampled over its extent (trace/soft, embree_soft_tile.hpp).
  void trace_layout(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out,
                    TraceStats& out_stats) override;
  // Hard fields' pairs answered from request's traces where the reuse rule allows (embree_reuse_tile.cpp).
  void trace_reusing(const Camera& camera, const VisibilityLayout& layout, const ReuseRequest& request,
                     VisibilityBuffer& out, TraceStats& out_stats) override;

  // Moves geometry (EmbreeScene::set_scene_time) and lights (light_at) to scene time `t`; does nothing for a scene
  // without animation. Not concurrent with tracing.
  void set_scene_time(double t, const NodeOverrides* overrides = nullptr) override;
  bool moves() const override { return !motion_.animation.empty(); }
  const SceneAnimation* scene_animation() const override { return moves() ? &motion_.animation : nullptr; }
  double last_motion_update_ms() const override { return scene_->motion_stats().last_update_ms; }
  double scene_time() const { return scene_->scene_time(); }

  // The Embree scene (e.g. to cast primary rays for a shaded preview with the same geometry).
  const EmbreeScene& embree_scene() const { return *scene_; }
  const EmbreeTracerConfig& config() const { return config_; }

 private:
  std::unique_ptr<EmbreeScene> scene_;
  // Traces the first layout.light_count lights into their fields (hard layout: one bit per light).
  // With `reuse`, answers are taken from its sources and recorded.
  void trace_fields(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out, TraceStats& out_stats,
                    const ReuseRequest* reuse = nullptr);

  std::vector<SceneLight> lights_;       // at the scene time
  std::vector<SceneLight> rest_lights_;  // as the Scene gives them
  LightSlots slots_;                     // the identity for at most kMaxLights lights
  // An animated scene: its animation, lights and meshes without vertices (node, T_world_local): what
  // set_scene_time reads. Empty for a static scene.
  Scene motion_;
  std::vector<SampledLight> sampled_;  // lights_ prepared for sampling (soft fields)
  TracerOptions options_;
  EmbreeTracerConfig config_;
  uint32_t threads_ = 1;
};

std::unique_ptr<VisibilityTracer> create_embree_tracer(const Scene& scene, const TracerOptions& options,
                                                       const EmbreeTracerConfig& config = {});

}  // namespace dhr::server
