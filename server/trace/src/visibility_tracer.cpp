// The interface's default light subset, for tracers that only implement trace() (e.g. wrappers); the Embree
// and Vulkan backends trace the subset directly.
#include "trace/visibility_tracer.hpp"

#include <stdexcept>
#include <string>
#include <utility>

namespace dhr::server {

void TraceStats::add_counts(const TraceStats& o) {
  pixels += o.pixels;
  background_pixels += o.background_pixels;
  primary_rays += o.primary_rays;
  shadow_rays += o.shadow_rays;
  skipped_backfacing += o.skipped_backfacing;
  skipped_out_of_range += o.skipped_out_of_range;
  skipped_culled_light += o.skipped_culled_light;
  soft_pairs += o.soft_pairs;
  soft_contributing_pairs += o.soft_contributing_pairs;
  soft_refined_pairs += o.soft_refined_pairs;
  soft_shadow_rays += o.soft_shadow_rays;
  reused_pixels += o.reused_pixels;
  reused_pairs += o.reused_pairs;
  refreshed_pixels += o.refreshed_pixels;
}

double TraceStats::soft_rays_per_pair() const {
  return soft_pairs ? static_cast<double>(soft_shadow_rays) / static_cast<double>(soft_pairs) : 0.0;
}

double TraceStats::soft_refined_share() const {
  return soft_contributing_pairs
             ? static_cast<double>(soft_refined_pairs) / static_cast<double>(soft_contributing_pairs)
             : 0.0;
}

void keep_first_lights(VisibilityBuffer& buffer, uint32_t lights) {
  if (lights >= buffer.light_count) return;
  VisibilityBuffer kept = VisibilityBuffer::create(buffer.width, buffer.height, lights);
  const uint32_t bits = kept.light_bits();
  const size_t n = buffer.pixel_count();
  for (size_t i = 0; i < n; ++i) kept.set_mask_at(i, buffer.mask_at(i) & bits);
  buffer = std::move(kept);
}

void check_trace_request(const Camera& camera, const VisibilityLayout& layout, uint32_t scene_lights) {
  if (layout.light_count > scene_lights)
    throw std::invalid_argument("trace: a layout of " + std::to_string(layout.light_count) + " lights, the scene has " +
                                std::to_string(scene_lights));
  if (auto err = validate_camera(camera)) throw std::invalid_argument("trace: " + *err);
  if (camera.extent.width > kMaxBufferDimension || camera.extent.height > kMaxBufferDimension)
    throw std::invalid_argument("trace: image exceeds " + std::to_string(kMaxBufferDimension) + " pixels per axis");
}

void VisibilityTracer::trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out,
                                    TraceStats& out_stats) {
  trace(camera, out, out_stats);
  keep_first_lights(out, lights);
}

VisibilityLayout layout_for_lights(const std::vector<bool>& extents, uint32_t lights) {
  if (extents.empty()) return VisibilityLayout::hard(lights);
  if (lights > extents.size())
    throw std::invalid_argument("layout: " + std::to_string(lights) + " lights of " + std::to_string(extents.size()));
  bool soft[kMaxLights] = {};
  for (uint32_t i = 0; i < lights && i < kMaxLights; ++i) soft[i] = extents[i];
  return VisibilityLayout::for_lights(std::span<const bool>(soft, lights));
}

void widen_to_layout(const VisibilityBuffer& hard, const VisibilityLayout& layout, VisibilityBuffer& out) {
  if (hard.light_count != layout.light_count)
    throw std::invalid_argument("widen_to_layout: " + std::to_string(hard.light_count) + " bits for " +
                                std::to_string(layout.light_count) + " lights");
  if (out.width != hard.width || out.height != hard.height || out.light_count != layout.total_bits())
    out = VisibilityBuffer::create(hard.width, hard.height, layout.total_bits());
  const size_t n = hard.pixel_count();
  for (size_t p = 0; p < n; ++p) {
    const uint32_t bits = hard.mask_at(p);
    uint32_t mask = 0;
    for (uint32_t i = 0; i < layout.light_count; ++i)
      mask = layout.with_visibility(mask, i, static_cast<float>((bits >> i) & 1u));
    out.set_mask_at(p, mask);
  }
}

void VisibilityTracer::trace_layout(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out,
                                    TraceStats& out_stats) {
  if (!layout.any_soft()) {
    trace_lights(camera, layout.light_count, out, out_stats);
    return;
  }
  thread_local VisibilityBuffer hard;
  trace_lights(camera, layout.light_count, hard, out_stats);
  widen_to_layout(hard, layout, out);
}

void VisibilityTracer::trace_reusing(const Camera& camera, const VisibilityLayout& layout,
                                     const ReuseRequest& request, VisibilityBuffer& out, TraceStats& out_stats) {
  trace_layout(camera, layout, out, out_stats);
  if (request.record) request.record->mesh.clear();
}

}  // namespace dhr::server
