// trace_bench's sequence mode, soft fields against a converged truth: every --truth-every'th frame the truth of
// each traced camera (trace_soft_image with dhr-eval's truth sampling: kTruthFirstSamples first samples and up to
// kTruthSamples where they disagree, an independent per-pixel scramble) and, for the exhaustive and the reusing trace of that camera, the
// sum of |k traced - k truth| over the surface pixels' soft lights (k traced: the field's level / 7). Their means
// are the JSON's visibility_error and exhaustive_visibility_error (issue 28: reuse must not raise it).
#pragma once
#include "eval/truth_sampling.hpp"
#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "trace/embree/embree_scene.hpp"
#include "trace/soft/soft_image.hpp"
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace dhr::bench {

// dhr-eval's ground-truth sampling (eval/truth_sampling.hpp): one definition of "converged" for both benchmarks.
using eval::kTruthFirstSamples;
using eval::kTruthSalt;
using eval::kTruthSamples;

struct TruthError {
  double sum = 0.0;    // of |k traced - k truth|
  uint64_t pairs = 0;  // surface pixels x soft lights
  double mean() const { return pairs > 0 ? sum / static_cast<double>(pairs) : 0.0; }
};

class SequenceTruth {
 public:
  // `lights`: the scene's lights at rest, the layout's first layout.light_count (a static scene).
  SequenceTruth(const server::EmbreeScene& scene, std::span<const SceneLight> lights, const VisibilityLayout& layout,
                unsigned threads);
  // Traces the truth of `camera` and adds both buffers' errors (buffers of that camera, in the layout).
  void add(const Camera& camera, const VisibilityBuffer& exhaustive, const VisibilityBuffer& reused);

  TruthError exhaustive, reused;
  uint32_t cameras = 0;
  double ms = 0.0;  // the truth's trace time, all cameras

 private:
  void accumulate(const VisibilityBuffer& buffer, TruthError& error) const;

  const server::EmbreeScene& scene_;
  std::vector<SceneLight> lights_;
  VisibilityLayout layout_;
  server::SoftImageOptions options_;
  server::SoftImage truth_;
};

}  // namespace dhr::bench
