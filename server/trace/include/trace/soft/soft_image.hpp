// Fractional (soft) visibility for a whole image: per pixel and light the fraction of the light the pixel's
// surface point sees, and its quantized level. Primary rays and surface points are the hard tracer's
// (embree_trace_tile.hpp's trace_primary_tile), the work split is its tile pool (tile_pool.hpp), and each
// pixel-light pair is soft_visibility (soft_visibility.hpp) with the seed SoftOptions::seed(x, y, light): each
// pixel's result depends only on its own rays, so the image is identical for any thread count and run.
// Not (yet) behind VisibilityTracer or on the wire.
#pragma once
#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "trace/embree/embree_scene.hpp"
#include "visibility/soft_levels.hpp"
#include "trace/soft/soft_visibility.hpp"
#include "trace/visibility_tracer.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace dhr::server {

struct SoftImageOptions {
  SoftOptions sampling;
  uint32_t levels = kDefaultSoftLevels;
  bool cull_lights = true;               // lights that cannot reach the view: 0 everywhere, no rays (SkipOptions)
  uint32_t threads = 0;                  // 0 = all cores, at most kMaxTracerThreads
  uint32_t tile_size = 16;               // a multiple of 4 (primary rays go in 4x4 packets)
  double primary_near = kClipNearPlane;  // as TracerOptions::primary_near
};

// Row-major, light-minor: index (y * width + x) * lights + light. Background pixels and lights that cannot
// contribute: fraction 0, level 0.
struct SoftImage {
  uint32_t width = 0, height = 0, lights = 0, levels = kDefaultSoftLevels;
  std::vector<float> fraction;
  std::vector<uint8_t> level;  // quantize(fraction, levels), plain binary (gray_encode for storage)
  std::vector<uint16_t> rays;  // occlusion rays traced for the pair (statistics, benchmarks)
  std::vector<uint8_t> surface;  // per pixel (y * width + x): 1 where the primary ray hit a surface
  size_t index(uint32_t x, uint32_t y, uint32_t light) const { return (size_t{y} * width + x) * lights + light; }
};

struct SoftStats {
  uint64_t pixels = 0;
  uint64_t background_pixels = 0;
  uint64_t primary_rays = 0;
  uint64_t pairs = 0;               // hit pixel x traced light (culled lights excluded)
  uint64_t contributing_pairs = 0;  // of those, the light test passed (samples were taken)
  uint64_t refined_pairs = 0;       // of those, the first samples disagreed
  uint64_t shadow_rays = 0;
  uint64_t skipped_backfacing = 0;
  uint64_t skipped_out_of_range = 0;  // incl. behind a one-sided emitter
  uint64_t skipped_culled_light = 0;
  uint32_t lights_culled = 0;
  double trace_ms = 0.0;  // wall time of the call

  // Occlusion rays per contributing pixel-light pair (0 when there is none).
  double rays_per_pair() const;
  // Share of contributing pairs that needed more than the first samples.
  double refined_share() const;
};

// Throws std::invalid_argument for an unusable camera or options, std::runtime_error for more than kMaxLights
// lights (or when a thread cannot start).
SoftStats trace_soft_image(const EmbreeScene& scene, std::span<const SceneLight> lights, const Camera& camera,
                           const SoftImageOptions& options, SoftImage& out);

}  // namespace dhr::server
