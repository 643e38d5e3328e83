// The reuse tests' step (tests/server): one camera traced exhaustively and reusing, and the bits that differ.
#pragma once
#include "trace/reuse/reuse_frame.hpp"
#include "trace/visibility_tracer.hpp"
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

#include <cstdint>

namespace dhr::server {

struct ReusePair {
  VisibilityBuffer exact, reused;
  TraceStats exact_stats, reused_stats;
};

// Traces `camera` both ways; the reusing trace takes from `previous` and records into `record`.
inline ReusePair trace_both(VisibilityTracer& tracer, const Camera& camera, const ReuseFrame* previous,
                            ReuseFrame& record, const ReuseOptions& options = {}) {
  ReusePair p;
  const VisibilityLayout layout = VisibilityLayout::hard(tracer.light_count());
  tracer.trace_layout(camera, layout, p.exact, p.exact_stats);
  ReuseRequest request;
  request.previous = previous;
  request.record = &record;
  request.options = options;
  tracer.trace_reusing(camera, layout, request, p.reused, p.reused_stats);
  return p;
}

inline uint64_t differing_bits(const VisibilityBuffer& a, const VisibilityBuffer& b) {
  uint64_t n = 0;
  for (size_t i = 0; i < a.pixel_count(); ++i)
    n += static_cast<uint64_t>(__builtin_popcount(a.mask_at(i) ^ b.mask_at(i)));
  return n;
}

}  // namespace dhr::server
