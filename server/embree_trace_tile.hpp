// Internal to the Embree tracer: everything one tile needs, and the tile kernel.
#pragma once
#include "core/lighting.hpp"
#include "embree_scene.hpp"
#include "embree_tracer.hpp"

#include <glm/mat3x3.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace dhr::server::detail {

// Per-frame constants shared read-only by all threads.
struct FrameSetup {
  const EmbreeScene* scene = nullptr;
  const Camera* camera = nullptr;
  glm::vec3 eye{0.0f};          // eye position in the scene's relative frame
  glm::dmat3 world_from_eye{1.0};
  std::vector<PackedLight> lights;      // all lights, relative frame
  std::vector<uint32_t> active_lights;  // indices of lights not culled for this view
  uint32_t culled_lights = 0;
  SkipOptions skip;
  bool primary_packets = true;
  ShadowQuery shadow_query = ShadowQuery::kStream;
};

// One queued occlusion ray's destination.
struct PendingShadowRay {
  uint32_t slot = 0;         // pixel slot within the tile (block * 16 + lane)
  uint32_t light = 0;        // light index (bit)
  bool contributes = false;  // light_test said kContributes (else traced only because a skip is off)
};

// Per-thread buffers reused from tile to tile.
struct TileScratch {
  std::vector<std::optional<SurfaceHit>> hits;
  std::vector<RTCRay> rays;
  std::vector<PendingShadowRay> pending;
  std::vector<uint32_t> masks;
};

// The frame constants for one camera: the eye in the scene's relative frame, the packed lights and which of
// them `skip.cull_lights` leaves active. Query kinds stay at their defaults (the tracer sets them).
FrameSetup make_frame_setup(const EmbreeScene& scene, const std::vector<SceneLight>& lights, const Camera& camera,
                            const SkipOptions& skip);

// Unit primary-ray direction through pixel (x, y)'s centre, relative frame.
glm::vec3 primary_direction(const FrameSetup& frame, uint32_t x, uint32_t y);

// One surface point and light: true with the occlusion ray to trace (and whether the light contributes, else
// the ray is traced only because a skip is off), or false when frame.skip skips the pair (counted in `stats`
// by reason). bench/trace_bench uses it to replay exactly the tracer's rays.
bool shadow_ray_for(const FrameSetup& frame, const PackedLight& light, const SurfaceHit& hit, TraceStats& stats,
                    RTCRay& out_ray, bool& out_contributes);

// Traces pixels [x0, x1) x [y0, y1) into `out` and adds to `stats` (counts only, no times).
void trace_tile(const FrameSetup& frame, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, VisibilityBuffer& out,
                TraceStats& stats, TileScratch& scratch);

}  // namespace dhr::server::detail
