// Internal to the Embree tracer: a tile's soft-light fields (VisibilityTracer::trace_layout with level fields).
// Runs after trace_tile, on the surface points that trace_tile left in its scratch, so the primary rays and the
// hard lights' bits are the hard tracer's; each soft pair is soft_visibility_batch with the seed
// soft_seed(x, y, light, salt), exactly as trace_soft_image (trace/soft/soft_image.hpp), so a soft field is the
// Gray code of quantize(trace_soft_image's fraction).
#pragma once
#include "trace/embree/embree_trace_tile.hpp"
#include "trace/soft/soft_visibility.hpp"
#include "visibility/visibility_layout.hpp"

#include <cstdint>
#include <vector>

namespace dhr::server::detail {

// A pair that accumulates onto earlier samples (trace/reuse, SoftTally) takes its run of new samples from the first
// this many of the light's sequence, cycling with the trace's generation.
inline constexpr uint32_t kSoftHistorySequence = 1024;

// Per-frame constants of the soft lights.
struct SoftTileSetup {
  const std::vector<SampledLight>* sampled = nullptr;  // every scene light, prepared for sampling
  std::vector<uint32_t> active;                         // soft lights the frame did not cull
  const VisibilityLayout* layout = nullptr;
  SoftOptions sampling;
};

// Per-thread buffers reused from tile to tile.
struct SoftTileScratch {
  std::vector<SoftPair> pairs;
  SoftScratch soft;
};

// Adds the soft lights' fields of the tile's hit pixels (scratch.hits / hit_pixels, as trace_tile left them) to
// `out` and their counts to `stats` (soft_* counters, shadow_rays, skipped_* by the whole-light test). A pair whose
// level reuse took (scratch.soft_known, rule 2 of trace/reuse) gets that level unsampled (counted in reused_pairs).
void trace_soft_tile(const FrameSetup& frame, const SoftTileSetup& soft, const TileScratch& scratch,
                     SoftTileScratch& soft_scratch, VisibilityBuffer& out, TraceStats& stats);

}  // namespace dhr::server::detail
