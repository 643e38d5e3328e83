// The interface's default light subset, for tracers that only implement trace() (e.g. wrappers); the Embree
// and Vulkan backends trace the subset directly.
#include "trace/visibility_tracer.hpp"

#include <utility>

namespace dhr::server {

void keep_first_lights(VisibilityBuffer& buffer, uint32_t lights) {
  if (lights >= buffer.light_count) return;
  VisibilityBuffer kept = VisibilityBuffer::create(buffer.width, buffer.height, lights);
  const uint32_t bits = kept.light_bits();
  const size_t n = buffer.pixel_count();
  for (size_t i = 0; i < n; ++i) kept.set_mask_at(i, buffer.mask_at(i) & bits);
  buffer = std::move(kept);
}

void VisibilityTracer::trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out,
                                    TraceStats& out_stats) {
  trace(camera, out, out_stats);
  keep_first_lights(out, lights);
}

}  // namespace dhr::server
