#include "sequence_truth.hpp"

#include <cmath>

namespace dhr::bench {

SequenceTruth::SequenceTruth(const server::EmbreeScene& scene, std::span<const SceneLight> lights,
                             const VisibilityLayout& layout, unsigned threads)
    : scene_(scene), lights_(lights.begin(), lights.begin() + layout.light_count), layout_(layout) {
  options_.sampling = server::SoftOptions{kTruthFirstSamples, kTruthSamples, kTruthSalt, server::SoftPattern::kPerPixel};
  options_.threads = threads;
}

void SequenceTruth::add(const Camera& camera, const VisibilityBuffer& exhaustive_buffer,
                        const VisibilityBuffer& reused_buffer) {
  const server::SoftStats stats = server::trace_soft_image(scene_, lights_, camera, options_, truth_);
  ms += stats.trace_ms;
  ++cameras;
  accumulate(exhaustive_buffer, exhaustive);
  accumulate(reused_buffer, reused);
}

void SequenceTruth::accumulate(const VisibilityBuffer& buffer, TruthError& error) const {
  for (uint32_t y = 0; y < truth_.height; ++y) {
    for (uint32_t x = 0; x < truth_.width; ++x) {
      if (!truth_.surface[size_t{y} * truth_.width + x]) continue;
      const uint32_t mask = buffer.get(x, y);
      for (uint32_t li = 0; li < layout_.light_count; ++li) {
        if (!layout_.is_soft(li)) continue;
        error.sum += std::fabs(static_cast<double>(layout_.visibility(mask, li)) -
                               static_cast<double>(truth_.fraction[truth_.index(x, y, li)]));
        ++error.pairs;
      }
    }
  }
}

}  // namespace dhr::bench
