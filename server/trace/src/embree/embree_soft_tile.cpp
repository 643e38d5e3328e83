#include "trace/embree/embree_soft_tile.hpp"

#include <algorithm>
#include <cmath>

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
  // What the eye's previous trace accumulated at the pair's point (trace/reuse: SoftTally), and where this trace's
  // tallies go.
  const uint32_t stride = scratch.history_stride;
  const ReuseSetup* reuse = frame.reuse;
  ReuseFrame* rec = reuse && reuse->record && !reuse->record->tally.empty() ? reuse->record : nullptr;
  const uint32_t cap = reuse ? reuse->options.soft_history : 0;
  auto slot_of = [&](uint32_t li) -> uint32_t { return reuse && li < kMaxLights ? reuse->history_slot[li] : 0xFFu; };
  auto history = [&](uint32_t li, size_t h) {
    const uint32_t slot = slot_of(li);
    return slot < stride ? scratch.soft_history[h * stride + slot] : SoftHistory{};
  };
  // A pair with history adds the first-sample count of a run of the sequence that moves on every trace (past the
  // max_samples a fresh pair may take), so the samples accumulated at a point are different ones.
  const uint32_t first_count = soft.sampling.initial_samples;
  const uint32_t run = soft.sampling.max_samples;
  const uint32_t runs = std::max(1u, (kSoftHistorySequence - run) / run);
  const uint32_t first = run + run * ((reuse ? reuse->generation : 0) % runs);
  auto accumulates = [&](const SoftHistory& hist) { return hist.samples >= static_cast<float>(first_count); };
  for (uint32_t li : soft.active)
    for (size_t h = 0; h < hits; ++h) {
      if (elsewhere(li, h) || taken(li, h)) continue;
      SoftPair pair;
      pair.light = &(*soft.sampled)[li];
      pair.hit = &scratch.hits[h];
      pair.seed = soft.sampling.seed(scratch.hit_pixels[h].x, scratch.hit_pixels[h].y, li);
      if (accumulates(history(li, h))) {
        // The first samples of this trace's run; where they disagree, as many more as the history lacks of the
        // max_samples a fresh pair takes (whole first-sample counts, within the run).
        const float short_of = static_cast<float>(run) - history(li, h).samples;
        pair.first = first;
        pair.count = first_count;
        pair.refine = short_of <= static_cast<float>(first_count)
                          ? first_count
                          : std::min(run, first_count * static_cast<uint32_t>(
                                                            std::ceil(short_of / static_cast<float>(first_count))));
      }
      batch.push_back(pair);
    }
  soft_visibility_batch(*frame.scene, batch, soft.sampling, soft_scratch.soft);
  size_t k = 0;
  for (uint32_t li : soft.active) {
    const uint32_t f = frame.field[li];
    for (size_t h = 0; h < hits; ++h) {
      if (elsewhere(li, h)) continue;
      ++stats.soft_pairs;
      const HitPixel& px = scratch.hit_pixels[h];
      const uint32_t kept = rec ? rec->tally_stride : 0, slot = slot_of(li);  // the record's tallies per pixel
      SoftTally* tally =
          slot < kept ? &rec->tally[(size_t{px.y} * rec->camera.extent.width + px.x) * kept + slot] : nullptr;
      if (taken(li, h)) {
        ++stats.reused_pairs;
        const uint32_t field = ((1u << soft.layout->bits[f]) - 1u) << soft.layout->offset[f];
        out.set(px.x, px.y, (out.get(px.x, px.y) & ~field) | (scratch.soft_mask[h] & field));
        // The taken level's samples stay accumulated there (the neighbours hold that level alike).
        if (tally) *tally = add_soft_samples(history(li, h), 0, 0, cap);
        continue;
      }
      const SoftPair& pair = batch[k++];
      const SoftSample& r = pair.result;
      if (r.test == LightTest::kBackfacing) ++stats.skipped_backfacing;
      if (r.test == LightTest::kOutOfRange || (r.test == LightTest::kContributes && r.samples == 0))
        ++stats.skipped_out_of_range;
      if (r.samples > 0) ++stats.soft_contributing_pairs;
      if (r.refined) ++stats.soft_refined_pairs;
      stats.soft_shadow_rays += r.rays;
      stats.shadow_rays += r.rays;
      float fraction = r.fraction;
      if (r.samples > 0 && (tally || pair.count > 0)) {
        const auto visible = static_cast<uint32_t>(std::lround(r.fraction * static_cast<float>(r.samples)));
        const SoftTally sum = add_soft_samples(pair.count > 0 ? history(li, h) : SoftHistory{}, visible, r.samples,
                                               std::max(cap, r.samples));
        if (pair.count > 0)
          fraction = soft_level_hysteresis(tally_fraction(sum), history(li, h).fraction,
                                           reuse->options.soft_hysteresis);
        if (tally) *tally = sum;
      }
      if (fraction <= 0.0f) continue;  // level 0 is Gray code 0: the field is already clear
      out.set(px.x, px.y, soft.layout->with_visibility(out.get(px.x, px.y), f, fraction));
    }
  }
}

}  // namespace dhr::server::detail
