#include "trace/embree/embree_tracer.hpp"

#include "trace/embree/embree_soft_tile.hpp"
#include "trace/embree/embree_trace_tile.hpp"
#include "trace/embree/tile_pool.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

namespace dhr::server {

EmbreeTracer::EmbreeTracer(const Scene& scene, const TracerOptions& options, const EmbreeTracerConfig& config)
    : lights_(scene.lights), options_(options), config_(config) {
  if (lights_.size() > kMaxSlotLights)
    throw std::runtime_error("embree tracer: " + std::to_string(lights_.size()) + " lights, at most " +
                             std::to_string(kMaxSlotLights) + " supported");
  // More than kMaxLights lights share the mask's fields (scene/light_slots.hpp), placed where they stand at rest.
  try {
    slots_ = LightSlots::assign(lights_);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("embree tracer: ") + e.what());
  }
  if (!slots_.is_identity() && !scene.animation.empty())
    throw std::runtime_error("embree tracer: " + std::to_string(lights_.size()) +
                             " lights share light slots, which need a scene without animation (more than " +
                             std::to_string(kMaxLights) + " lights in a moving scene are not supported)");
  if (config_.tile_size == 0 || config_.tile_size % 4 != 0)
    throw std::runtime_error("embree tracer: tile size must be a positive multiple of 4");
  if (auto err = validate_soft_options(options_.soft)) throw std::runtime_error("embree tracer: " + *err);
  if (options.threads > kMaxTracerThreads)
    throw std::invalid_argument("embree tracer: " + std::to_string(options.threads) + " threads, at most " +
                                std::to_string(kMaxTracerThreads));
  threads_ = options.threads ? options.threads
                             : std::clamp(std::thread::hardware_concurrency(), 1u, kMaxTracerThreads);
  EmbreeBuildOptions build = config_.build;
  if (build.threads == 0) build.threads = threads_;
  scene_ = EmbreeScene::create(scene, build);
  for (const SceneLight& l : lights_) sampled_.push_back(make_sampled_light(l, scene_->origin()));
  rest_lights_ = lights_;
  if (!scene.animation.empty()) {
    motion_.animation = scene.animation;
    motion_.lights = scene.lights;
    motion_.meshes.reserve(scene.meshes.size());
    for (const SceneMesh& m : scene.meshes) {
      SceneMesh& meta = motion_.meshes.emplace_back();
      meta.name = m.name;
      meta.node = m.node;
      meta.T_world_local = m.T_world_local;
    }
  }
}

void EmbreeTracer::set_scene_time(double t, const NodeOverrides* overrides) {
  if (motion_.animation.empty()) return;
  scene_->set_scene_time(motion_, t, overrides);
  for (size_t i = 0; i < lights_.size(); ++i) {
    lights_[i] = light_at(motion_, rest_lights_[i], t, overrides);
    sampled_[i] = make_sampled_light(lights_[i], scene_->origin());
  }
}

EmbreeTracer::~EmbreeTracer() = default;

std::string EmbreeTracer::device_description() const { return scene_->description(threads_); }
const AccelStats& EmbreeTracer::accel_stats() const { return scene_->stats(); }
uint32_t EmbreeTracer::light_count() const { return slots_.slot_count(); }
const LightSlots* EmbreeTracer::light_slots() const { return slots_.is_identity() ? nullptr : &slots_; }

void EmbreeTracer::trace(const Camera& camera, VisibilityBuffer& out, TraceStats& out_stats) {
  trace_lights(camera, light_count(), out, out_stats);
}

std::vector<bool> EmbreeTracer::light_extents() const {
  return slots_.soft_slots();  // the identity's: each light's extent
}

void EmbreeTracer::trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out,
                                TraceStats& out_stats) {
  trace_fields(camera, VisibilityLayout::hard(std::min(lights, light_count())), out, out_stats);
}

void EmbreeTracer::trace_layout(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out,
                                TraceStats& out_stats) {
  trace_fields(camera, layout, out, out_stats);
}

void EmbreeTracer::trace_reusing(const Camera& camera, const VisibilityLayout& layout, const ReuseRequest& request,
                                 VisibilityBuffer& out, TraceStats& out_stats) {
  trace_fields(camera, layout, out, out_stats, &request);
}

void EmbreeTracer::trace_fields(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out,
                                TraceStats& out_stats, const ReuseRequest* reuse) {
  const auto t0 = std::chrono::steady_clock::now();
  check_trace_request(camera, layout, light_count());

  const uint32_t width = camera.extent.width, height = camera.extent.height;
  const uint32_t lights = layout.light_count, bits = layout.total_bits();
  if (out.width != width || out.height != height || out.light_count != bits)
    out = VisibilityBuffer::create(width, height, bits);

  detail::FrameSetup frame = detail::make_frame_setup(*scene_, lights_, camera, options_.skip, lights, light_slots());
  frame.primary_near = options_.primary_near;
  frame.primary_packets = config_.primary_packets;
  frame.shadow_query = config_.shadow_query;
  // A layout with level fields: hard lights to their bit, soft lights (not culled) to trace_soft_tile. Culling
  // (light_may_reach_view) takes or leaves a soft light's field as a whole.
  detail::SoftTileSetup soft;
  soft.sampled = &sampled_;
  soft.layout = &layout;
  soft.sampling = options_.soft;
  if (layout.any_soft()) {
    std::vector<uint32_t> hard;
    for (uint32_t li : frame.active_lights) {
      const bool is_soft = layout.is_soft(frame.field[li]);
      (is_soft ? soft.active : hard).push_back(li);
      if (frame.slots) frame.light_state[li] = is_soft ? detail::kLightSoft : detail::kLightHard;
    }
    frame.active_lights = std::move(hard);
    for (uint32_t i = 0; i < lights_.size(); ++i)
      if (frame.field[i] < kMaxLights) frame.bit[i] = layout.offset[frame.field[i]];
    if (frame.slots) {
      frame.idle_lit = 0;
      for (uint32_t f = 0; f < frame.fields; ++f)
        if (!layout.is_soft(f)) frame.idle_lit |= 1u << layout.offset[f];
    }
  }

  detail::ReuseSetup reuse_setup;
  if (reuse) {
    reuse_setup = detail::make_reuse_setup(*scene_, frame, *reuse, layout, scene_->scene_time());
    frame.reuse = &reuse_setup;
  }

  const uint32_t tile = config_.tile_size;
  const uint32_t tiles_x = (width + tile - 1) / tile, tiles_y = (height + tile - 1) / tile;
  const uint32_t tile_count = tiles_x * tiles_y;
  const uint32_t workers = tile_workers(threads_, tile_count);
  std::vector<TraceStats> partial(workers);
  std::vector<detail::TileScratch> scratch(workers);
  std::vector<detail::SoftTileScratch> soft_scratch(soft.active.empty() ? 0 : workers);
  // Each pixel's bits depend only on its own rays, so the image is the same whichever thread traced it.
  // Counters are summed per thread: integers, exact.
  run_tiles(
      workers, tile_count,
      [&](uint32_t worker, uint32_t t) {
        const uint32_t x0 = (t % tiles_x) * tile, y0 = (t / tiles_x) * tile;
        detail::trace_tile(frame, x0, y0, std::min(x0 + tile, width), std::min(y0 + tile, height), out,
                           partial[worker], scratch[worker]);
        if (!soft.active.empty())
          detail::trace_soft_tile(frame, soft, scratch[worker], soft_scratch[worker], out, partial[worker]);
        if (frame.reuse) detail::record_reuse_tile(frame, scratch[worker], out);
      },
      "embree tracer");
  if (frame.reuse) detail::finish_reuse_record(frame, workers);

  TraceStats stats;
  stats.pixels = static_cast<uint64_t>(width) * height;
  stats.lights_culled = frame.culled_lights;
  stats.lights_unrequested = light_count() - lights;
  for (const TraceStats& p : partial) stats.add_counts(p);  // the tiles count no pixels: stats.pixels stays
  stats.trace_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  stats.gpu_ms = -1.0;
  out_stats = stats;
}

std::unique_ptr<VisibilityTracer> create_embree_tracer(const Scene& scene, const TracerOptions& options,
                                                       const EmbreeTracerConfig& config) {
  return std::make_unique<EmbreeTracer>(scene, options, config);
}

}  // namespace dhr::server
