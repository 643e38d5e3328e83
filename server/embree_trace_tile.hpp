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

// Traces pixels [x0, x1) x [y0, y1) into `out` and adds to `stats` (counts only, no times).
void trace_tile(const FrameSetup& frame, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, VisibilityBuffer& out,
                TraceStats& stats, TileScratch& scratch);

}  // namespace dhr::server::detail
