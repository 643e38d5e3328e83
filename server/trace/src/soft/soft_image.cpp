#include "trace/soft/soft_image.hpp"

#include "trace/embree/embree_trace_tile.hpp"
#include "trace/embree/tile_pool.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

namespace dhr::server {

double SoftStats::rays_per_pair() const {
  return contributing_pairs ? static_cast<double>(shadow_rays) / static_cast<double>(contributing_pairs) : 0.0;
}

double SoftStats::refined_share() const {
  return contributing_pairs ? static_cast<double>(refined_pairs) / static_cast<double>(contributing_pairs) : 0.0;
}

SoftStats trace_soft_image(const EmbreeScene& scene, std::span<const SceneLight> lights, const Camera& camera,
                           const SoftImageOptions& options, SoftImage& out) {
  const auto t0 = std::chrono::steady_clock::now();
  if (auto err = validate_camera(camera)) throw std::invalid_argument("soft trace: " + *err);
  if (camera.extent.width > kMaxBufferDimension || camera.extent.height > kMaxBufferDimension)
    throw std::invalid_argument("soft trace: image exceeds " + std::to_string(kMaxBufferDimension) + " pixels per axis");
  if (auto err = validate_soft_options(options.sampling)) throw std::invalid_argument(*err);
  if (options.levels < kMinSoftLevels || options.levels > kMaxSoftLevels)
    throw std::invalid_argument("soft trace: levels must be in [2, 256]");
  if (options.tile_size == 0 || options.tile_size % 4 != 0)
    throw std::invalid_argument("soft trace: tile size must be a positive multiple of 4");
  if (options.threads > kMaxTracerThreads) throw std::invalid_argument("soft trace: too many threads");
  if (lights.size() > kMaxLights)
    throw std::runtime_error("soft trace: " + std::to_string(lights.size()) + " lights, at most " +
                             std::to_string(kMaxLights) + " supported");

  const uint32_t width = camera.extent.width, height = camera.extent.height;
  const uint32_t light_count = static_cast<uint32_t>(lights.size());
  out.width = width;
  out.height = height;
  out.lights = light_count;
  out.levels = options.levels;
  out.fraction.assign(size_t{width} * height * light_count, 0.0f);
  out.level.assign(out.fraction.size(), 0);
  out.rays.assign(out.fraction.size(), 0);
  out.surface.assign(size_t{width} * height, 0);

  // The hard tracer's frame: eye, primary-ray tables, light culling. Only the cull skip matters here: the
  // other pairs that cannot contribute are skipped by soft_visibility's own light test (their k is 0 either way).
  SkipOptions skip;
  skip.cull_lights = options.cull_lights;
  const std::vector<SceneLight> light_list(lights.begin(), lights.end());
  detail::FrameSetup frame = detail::make_frame_setup(scene, light_list, camera, skip);
  frame.primary_near = options.primary_near;
  std::vector<SampledLight> sampled;
  sampled.reserve(light_count);
  for (const SceneLight& l : lights) sampled.push_back(make_sampled_light(l, scene.origin()));

  const uint32_t threads =
      options.threads ? options.threads : std::clamp(std::thread::hardware_concurrency(), 1u, kMaxTracerThreads);
  const uint32_t tile = options.tile_size;
  const uint32_t tiles_x = (width + tile - 1) / tile, tiles_y = (height + tile - 1) / tile;
  const uint32_t tile_count = tiles_x * tiles_y;
  const uint32_t workers = tile_workers(threads, tile_count);
  std::vector<SoftStats> partial(workers);
  std::vector<TraceStats> primary(workers);
  std::vector<detail::TileScratch> scratch(workers);
  std::vector<std::vector<SoftPair>> pairs(workers);
  std::vector<SoftScratch> soft_scratch(workers);
  run_tiles(
      workers, tile_count,
      [&](uint32_t worker, uint32_t t) {
        const uint32_t x0 = (t % tiles_x) * tile, y0 = (t / tiles_x) * tile;
        detail::TileScratch& s = scratch[worker];
        detail::trace_primary_tile(frame, x0, y0, std::min(x0 + tile, width), std::min(y0 + tile, height), s,
                                   primary[worker]);
        SoftStats& st = partial[worker];
        // Light-major, then hit order: runs of neighbouring pixels toward one light (coherent streams).
        std::vector<SoftPair>& batch = pairs[worker];
        batch.clear();
        for (uint32_t li : frame.active_lights)
          for (size_t h = 0; h < s.hits.size(); ++h)
            batch.push_back({&sampled[li], &s.hits[h],
                             options.sampling.seed(s.hit_pixels[h].x, s.hit_pixels[h].y, li), 0, 0, 0, {}});
        soft_visibility_batch(scene, batch, options.sampling, soft_scratch[worker]);
        for (const auto& pixel : s.hit_pixels) out.surface[size_t{pixel.y} * width + pixel.x] = 1;
        size_t k = 0;
        for (uint32_t li : frame.active_lights) {
          for (size_t h = 0; h < s.hits.size(); ++h, ++k) {
            const SoftSample& r = batch[k].result;
            ++st.pairs;
            if (r.test == LightTest::kBackfacing) ++st.skipped_backfacing;
            if (r.test == LightTest::kOutOfRange || (r.test == LightTest::kContributes && r.samples == 0))
              ++st.skipped_out_of_range;
            if (r.samples > 0) ++st.contributing_pairs;
            if (r.refined) ++st.refined_pairs;
            st.shadow_rays += r.rays;
            const size_t i = out.index(s.hit_pixels[h].x, s.hit_pixels[h].y, li);
            out.fraction[i] = r.fraction;
            out.level[i] = static_cast<uint8_t>(quantize(r.fraction, options.levels));
            out.rays[i] = static_cast<uint16_t>(r.rays);
          }
        }
      },
      "soft trace");

  SoftStats stats;
  stats.pixels = uint64_t{width} * height;
  stats.lights_culled = frame.culled_lights;
  for (uint32_t w = 0; w < workers; ++w) {
    const SoftStats& p = partial[w];
    stats.background_pixels += primary[w].background_pixels;
    stats.primary_rays += primary[w].primary_rays;
    stats.pairs += p.pairs;
    stats.contributing_pairs += p.contributing_pairs;
    stats.refined_pairs += p.refined_pairs;
    stats.shadow_rays += p.shadow_rays;
    stats.skipped_backfacing += p.skipped_backfacing;
    stats.skipped_out_of_range += p.skipped_out_of_range;
  }
  stats.skipped_culled_light = (stats.pixels - stats.background_pixels) * frame.culled_lights;
  stats.trace_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace dhr::server
