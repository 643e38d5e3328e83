// Fractional visibility of one surface point to one light: the share of samples over the light's extent
// (trace/soft/light_sampler.hpp) that reach it, by Embree occlusion queries with the hard tracer's ray-offset and
// tfar rules.
//
// Whole-light test first (light_eval's light_test at the light's centre, with the shading normal, exactly as
// the hard tracer): a light that cannot contribute there (out of range or cone, N.L <= 0) gets 0 and no ray,
// as the shading equation multiplies k by saturate(N.L) toward the centre anyway. The ray origin is the hard
// tracer's: offset along the geometric normal on the side of the light's centre. A sample below that side's
// horizon is hidden by the surface itself: it counts as occluded and costs no ray.
//
// Adaptive: the first `initial_samples` samples (a stratified net over the light); when they all agree (all
// reach the light or none) that is the answer; otherwise samples up to `max_samples` are taken and the fraction
// is over all of them. A punctual light takes exactly one sample, the hard tracer's ray, so its fraction is
// today's bit.
#pragma once
#include "trace/embree/embree_scene.hpp"
#include "trace/soft/light_sampler.hpp"
#include "trace/soft/soft_options.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dhr::server {

struct SoftSample {
  float fraction = 0.0f;       // visible samples / samples taken
  uint32_t rays = 0;           // occlusion rays traced
  uint32_t samples = 0;        // samples taken (rays + those below the horizon); 0 when the light cannot contribute
  bool refined = false;        // the first samples disagreed and max_samples were taken
  LightTest test = LightTest::kContributes;  // the whole-light test at the centre
};

// `hit`: the surface point (EmbreeScene's relative frame, as EmbreeScene::surface gives it); `seed`: soft_seed
// of its pixel and light. Deterministic: the same inputs give the same result.
SoftSample soft_visibility(const EmbreeScene& scene, const SampledLight& light, const SurfaceHit& hit, uint32_t seed,
                           const SoftOptions& options);

// The same for many pairs at once, in two rounds of occlusion queries (all first samples, then the refinements),
// each handed to Embree as one stream (rtcOccluded1M, as the hard tracer's tiles): what the image's tiles use.
// soft_visibility is this with one pair.
struct SoftPair {
  const SampledLight* light = nullptr;
  const SurfaceHit* hit = nullptr;
  uint32_t seed = 0;
  // count > 0: samples [first, first + count) of the sequence, then up to [first, first + refine) when those
  // disagree (what accumulates onto samples an earlier trace took: trace/reuse, SoftTally); 0: the adaptive rule
  // from sample 0.
  uint32_t first = 0;
  uint32_t count = 0;
  uint32_t refine = 0;
  SoftSample result;  // out
};

// Reused buffers (one per thread).
struct SoftScratch {
  struct State;  // per pair: how it is sampled (soft_visibility.cpp)
  std::vector<State> states;
  std::vector<RTCRay> rays;
  std::vector<uint32_t> owner;  // pair of each ray
  // With one scramble per light (SoftPattern::kPerLight): the sample points of the last few (seed, shape) prepared,
  // the sequence's first points.size() points. A batch is light-major, so one entry serves a light's every pair.
  struct Prepared {
    uint32_t seed = 0;
    SampledLight::Shape shape = SampledLight::Shape::kPunctual;
    std::vector<SamplePoint> points;
  };
  std::vector<Prepared> prepared;
  size_t prepared_next = 0;  // the entry replaced next when all are taken
  SoftScratch();
  ~SoftScratch();
};

void soft_visibility_batch(const EmbreeScene& scene, std::span<SoftPair> pairs, const SoftOptions& options,
                           SoftScratch& scratch);

}  // namespace dhr::server
