#include "trace/embree/embree_soft_tile.hpp"

namespace dhr::server::detail {

void trace_soft_tile(const FrameSetup& frame, const SoftTileSetup& soft, const TileScratch& scratch,
                     SoftTileScratch& soft_scratch, VisibilityBuffer& out, TraceStats& stats) {
  const size_t hits = scratch.hits.size();
  if (soft.active.empty() || hits == 0) return;
  // Light-major, then hit order (as trace_soft_image): runs of neighbouring pixels toward one light.
  std::vector<SoftPair>& batch = soft_scratch.pairs;
  batch.clear();
  // A pair whose level reuse took (TileScratch::soft_known) is not sampled: its field is written as taken.
  auto taken = [&](uint32_t li, size_t h) {
    return !scratch.soft_known.empty() && (scratch.soft_known[h] >> frame.field[li] & 1u);
  };
  // With light slots, a light's pairs are those of the hits whose cell holds it.
  auto elsewhere = [&](uint32_t li, size_t h) { return frame.slots && scratch.cell_lights[h][frame.field[li]] != li; };
  for (uint32_t li : soft.active)
    for (size_t h = 0; h < hits; ++h) {
      if (elsewhere(li, h) || taken(li, h)) continue;
      batch.push_back({&(*soft.sampled)[li], &scratch.hits[h],
                       soft.sampling.seed(scratch.hit_pixels[h].x, scratch.hit_pixels[h].y, li), {}});
    }
  soft_visibility_batch(*frame.scene, batch, soft.sampling, soft_scratch.soft);
  size_t k = 0;
  for (uint32_t li : soft.active) {
    const uint32_t f = frame.field[li];
    for (size_t h = 0; h < hits; ++h) {
      if (elsewhere(li, h)) continue;
      ++stats.soft_pairs;
      const HitPixel& px = scratch.hit_pixels[h];
      if (taken(li, h)) {
        ++stats.reused_pairs;
        const uint32_t field = ((1u << soft.layout->bits[f]) - 1u) << soft.layout->offset[f];
        out.set(px.x, px.y, (out.get(px.x, px.y) & ~field) | (scratch.soft_mask[h] & field));
        continue;
      }
      const SoftSample& r = batch[k++].result;
      if (r.test == LightTest::kBackfacing) ++stats.skipped_backfacing;
      if (r.test == LightTest::kOutOfRange || (r.test == LightTest::kContributes && r.samples == 0))
        ++stats.skipped_out_of_range;
      if (r.samples > 0) ++stats.soft_contributing_pairs;
      if (r.refined) ++stats.soft_refined_pairs;
      stats.soft_shadow_rays += r.rays;
      stats.shadow_rays += r.rays;
      if (r.fraction <= 0.0f) continue;  // level 0 is Gray code 0: the field is already clear
      out.set(px.x, px.y, soft.layout->with_visibility(out.get(px.x, px.y), f, r.fraction));
    }
  }
}

}  // namespace dhr::server::detail
