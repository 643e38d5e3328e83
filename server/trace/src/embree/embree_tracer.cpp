#include "trace/embree/embree_tracer.hpp"

#include "trace/embree/embree_trace_tile.hpp"
#include "trace/embree/tile_pool.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

namespace dhr::server {

EmbreeTracer::EmbreeTracer(const Scene& scene, const TracerOptions& options, const EmbreeTracerConfig& config)
    : lights_(scene.lights), options_(options), config_(config) {
  if (lights_.size() > kMaxLights)
    throw std::runtime_error("embree tracer: " + std::to_string(lights_.size()) + " lights, at most " +
                             std::to_string(kMaxLights) + " supported");
  if (config_.tile_size == 0 || config_.tile_size % 4 != 0)
    throw std::runtime_error("embree tracer: tile size must be a positive multiple of 4");
  if (options.threads > kMaxTracerThreads)
    throw std::invalid_argument("embree tracer: " + std::to_string(options.threads) + " threads, at most " +
                                std::to_string(kMaxTracerThreads));
  threads_ = options.threads ? options.threads
                             : std::clamp(std::thread::hardware_concurrency(), 1u, kMaxTracerThreads);
  EmbreeBuildOptions build = config_.build;
  if (build.threads == 0) build.threads = threads_;
  scene_ = EmbreeScene::create(scene, build);
}

EmbreeTracer::~EmbreeTracer() = default;

std::string EmbreeTracer::device_description() const { return scene_->description(threads_); }
const AccelStats& EmbreeTracer::accel_stats() const { return scene_->stats(); }
uint32_t EmbreeTracer::light_count() const { return static_cast<uint32_t>(lights_.size()); }

void EmbreeTracer::trace(const Camera& camera, VisibilityBuffer& out, TraceStats& out_stats) {
  trace_lights(camera, light_count(), out, out_stats);
}

void EmbreeTracer::trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out,
                                TraceStats& out_stats) {
  const auto t0 = std::chrono::steady_clock::now();
  if (auto err = validate_camera(camera)) throw std::invalid_argument("trace: " + *err);
  if (camera.extent.width > kMaxBufferDimension || camera.extent.height > kMaxBufferDimension)
    throw std::invalid_argument("trace: image exceeds " + std::to_string(kMaxBufferDimension) + " pixels per axis");

  const uint32_t width = camera.extent.width, height = camera.extent.height;
  lights = std::min(lights, light_count());
  if (out.width != width || out.height != height || out.light_count != lights)
    out = VisibilityBuffer::create(width, height, lights);

  detail::FrameSetup frame = detail::make_frame_setup(*scene_, lights_, camera, options_.skip, lights);
  frame.primary_near = options_.primary_near;
  frame.primary_packets = config_.primary_packets;
  frame.shadow_query = config_.shadow_query;

  const uint32_t tile = config_.tile_size;
  const uint32_t tiles_x = (width + tile - 1) / tile, tiles_y = (height + tile - 1) / tile;
  const uint32_t tile_count = tiles_x * tiles_y;
  const uint32_t workers = tile_workers(threads_, tile_count);
  std::vector<TraceStats> partial(workers);
  std::vector<detail::TileScratch> scratch(workers);
  // Each pixel's bits depend only on its own rays, so the image is the same whichever thread traced it.
  // Counters are summed per thread: integers, exact.
  run_tiles(
      workers, tile_count,
      [&](uint32_t worker, uint32_t t) {
        const uint32_t x0 = (t % tiles_x) * tile, y0 = (t / tiles_x) * tile;
        detail::trace_tile(frame, x0, y0, std::min(x0 + tile, width), std::min(y0 + tile, height), out,
                           partial[worker], scratch[worker]);
      },
      "embree tracer");

  TraceStats stats;
  stats.pixels = static_cast<uint64_t>(width) * height;
  stats.lights_culled = frame.culled_lights;
  stats.lights_unrequested = light_count() - lights;
  for (const TraceStats& p : partial) {
    stats.background_pixels += p.background_pixels;
    stats.primary_rays += p.primary_rays;
    stats.shadow_rays += p.shadow_rays;
    stats.skipped_backfacing += p.skipped_backfacing;
    stats.skipped_out_of_range += p.skipped_out_of_range;
    stats.skipped_culled_light += p.skipped_culled_light;
  }
  stats.trace_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  stats.gpu_ms = -1.0;
  out_stats = stats;
}

std::unique_ptr<VisibilityTracer> create_embree_tracer(const Scene& scene, const TracerOptions& options,
                                                       const EmbreeTracerConfig& config) {
  return std::make_unique<EmbreeTracer>(scene, options, config);
}

}  // namespace dhr::server
