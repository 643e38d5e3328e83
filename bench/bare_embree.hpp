// The "bare Embree" reference of bench/trace_bench: the server tracer's exact rays for one eye, captured
// once (untimed), then traced by a minimal loop of rtcIntersect1 (primary) and rtcOccluded1 (shadow) calls
// on the same Embree scene with the same thread count. What the tracer adds on top (ray generation,
// surface reconstruction, light tests, packing bits) shows up as the gap between the two rays/s figures.
#pragma once
#include "trace/embree/embree_scene.hpp"
#include "trace/visibility_tracer.hpp"

#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

namespace dhr::bench {

struct CapturedRays {
  std::vector<RTCRayHit> primary;  // one per pixel, row-major
  std::vector<RTCRay> shadow;      // the occlusion rays the tracer traces for this view and skip setting
  std::vector<float> shadow_tfar;  // each shadow ray's tfar before tracing (Embree overwrites it)
  uint64_t primary_hits = 0;       // pixels whose primary ray hit (single-ray queries)
};

// The rays of camera's view as EmbreeTracer traces them (server/trace/include/trace/embree/embree_trace_tile.hpp's per-pixel
// functions), using `threads` threads. Pixels are independent, so the rays do not depend on `threads`.
CapturedRays capture_rays(const server::EmbreeScene& scene, const std::vector<SceneLight>& lights,
                          const Camera& camera, const server::SkipOptions& skip, unsigned threads);

// CPU time used by this process so far (all threads), in ms: steadier than wall time on a shared machine.
double process_cpu_ms();

struct BareLoopResult {
  double primary_ms = 0.0;  // wall time of the rtcIntersect1 pass
  double shadow_ms = 0.0;   // wall time of the rtcOccluded1 pass
  double cpu_ms = 0.0;      // process CPU time of both passes
  uint64_t primary_hits = 0;
  uint64_t occluded = 0;    // shadow rays that hit something
};

// Traces every captured ray once (rays are reset first, so it can run repeatedly).
BareLoopResult run_bare_loop(RTCScene scene, CapturedRays& rays, unsigned threads);

}  // namespace dhr::bench
