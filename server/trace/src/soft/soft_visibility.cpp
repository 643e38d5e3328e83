#include "trace/soft/soft_visibility.hpp"

#include "trace/embree/embree_trace_tile.hpp"
#include "trace/ray_offset.hpp"

#include <glm/geometric.hpp>

namespace dhr::server {

// How one pair is sampled, set by begin_pair.
struct SoftScratch::State {
  enum class Kind : uint8_t { kDone, kHard, kExtent };
  Kind kind = Kind::kDone;
  RTCRay hard_ray{};
  glm::vec3 origin{0.0f}, n{0.0f};
  std::optional<LightView> view;
  uint32_t visible = 0;
};

SoftScratch::SoftScratch() = default;
SoftScratch::~SoftScratch() = default;

namespace {

using State = SoftScratch::State;

// The whole-light test, then how the pair is sampled: not at all (the light cannot contribute, or the point is
// behind a one-sided emitter), the hard tracer's one ray, or samples over the extent.
State begin_pair(const EmbreeScene& scene, SoftPair& pair) {
  State st;
  const SampledLight& light = *pair.light;
  const SurfaceHit& hit = *pair.hit;
  const LightSample centre = sample_light(light.packed, hit.position, hit.shading_normal);
  pair.result = SoftSample{};
  pair.result.test = centre.test;
  if (centre.test != LightTest::kContributes) return st;
  auto hard = [&] {
    st.kind = State::Kind::kHard;
    detail::make_shadow_ray(light.packed, hit, centre, scene.ray_offset(), st.hard_ray);
    return st;
  };
  if (light.shape == SampledLight::Shape::kPunctual) return hard();
  // The hard tracer's origin: leave from the side of the surface the light's centre is on.
  st.n = glm::dot(hit.geometric_normal, centre.l) >= 0.0f ? hit.geometric_normal : -hit.geometric_normal;
  st.origin = offset_ray_origin(hit.position, st.n, scene.ray_offset());
  st.view = LightView::create(light, st.origin);
  if (st.view) {
    st.kind = State::Kind::kExtent;
    return st;
  }
  if (light.one_sided()) return st;  // behind (or in the plane of) a one-sided emitter: nothing arrives
  return hard();                     // inside a sphere light: no cap to sample; the ray toward its centre decides
}

// (seed, shape) entries kept. A batch is light-major, so one entry is in use at a time; a few keep each light's points
// from the first round of queries to the second (more soft lights than this make them again: the same points).
constexpr size_t kPreparedEntries = 4;

// The first `count` sample points of `seed` prepared for `shape`, from the scratch's entries (made or extended here).
const SamplePoint* prepared_points(SoftScratch& scratch, uint32_t seed, SampledLight::Shape shape, uint32_t count) {
  SoftScratch::Prepared* entry = nullptr;
  for (SoftScratch::Prepared& e : scratch.prepared)
    if (e.seed == seed && e.shape == shape) entry = &e;
  if (entry == nullptr) {
    if (scratch.prepared.size() < kPreparedEntries) {
      entry = &scratch.prepared.emplace_back();
    } else {
      entry = &scratch.prepared[scratch.prepared_next];
      scratch.prepared_next = (scratch.prepared_next + 1) % kPreparedEntries;
    }
    entry->seed = seed;
    entry->shape = shape;
    entry->points.clear();
  }
  for (uint32_t i = static_cast<uint32_t>(entry->points.size()); i < count; ++i)
    entry->points.push_back(prepare_sample(shape, sample_2d(i, seed)));
  return entry->points.data();
}

// Rays of samples [begin, end) of pair `index`; a sample below the horizon of the origin's side is hidden by the
// surface itself: it counts as occluded and costs no ray. `points`: the pair's prepared sample points (at least
// `end`), or null to prepare each here (a scramble per pixel: nothing to share).
void append_samples(const SoftPair& pair, const State& st, uint32_t index, uint32_t begin, uint32_t end,
                    const SamplePoint* points, SoftScratch& scratch) {
  for (uint32_t i = begin; i < end; ++i) {
    const SampleRay s =
        points != nullptr ? st.view->sample(points[i]) : st.view->sample(sample_2d(i, pair.seed));
    if (!(glm::dot(st.n, s.dir) > 0.0f)) continue;
    scratch.rays.push_back(make_rtc_ray(st.origin, s.dir, s.tfar));
    scratch.owner.push_back(index);
  }
}

// Occlusion queries for the queued rays; each ray that reaches its light counts for its pair.
void trace_queued(const EmbreeScene& scene, SoftScratch& scratch, std::span<SoftPair> pairs) {
  if (scratch.rays.empty()) return;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  // Rays of one pair leave one point, and neighbouring pairs are neighbouring pixels toward the same light.
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcOccluded1M(scene.handle(), &context, scratch.rays.data(), static_cast<unsigned>(scratch.rays.size()),
                sizeof(RTCRay));
  for (size_t r = 0; r < scratch.rays.size(); ++r) {
    ++pairs[scratch.owner[r]].result.rays;
    if (scratch.rays[r].tfar >= 0.0f) ++scratch.states[scratch.owner[r]].visible;  // occluded: tfar = -inf
  }
  scratch.rays.clear();
  scratch.owner.clear();
}

}  // namespace

std::optional<std::string> validate_soft_options(const SoftOptions& o) {
  if (o.initial_samples == 0) return "soft visibility: initial samples must be at least 1";
  if (o.max_samples < o.initial_samples) return "soft visibility: max samples below initial samples";
  if (o.max_samples > kMaxSoftSamples)
    return "soft visibility: more than " + std::to_string(kMaxSoftSamples) + " samples";
  return std::nullopt;
}

void soft_visibility_batch(const EmbreeScene& scene, std::span<SoftPair> pairs, const SoftOptions& options,
                           SoftScratch& scratch) {
  scratch.states.clear();
  scratch.rays.clear();
  scratch.owner.clear();
  // One scramble per light: every pair of a light samples the same points, prepared once (bit for bit the same).
  const bool shared_points = options.pattern == SoftPattern::kPerLight;
  auto points_for = [&](const SoftPair& pair, uint32_t count) -> const SamplePoint* {
    return shared_points ? prepared_points(scratch, pair.seed, pair.light->shape, count) : nullptr;
  };
  // Round 1: the hard rays and every pair's first samples.
  for (uint32_t i = 0; i < pairs.size(); ++i) {
    scratch.states.push_back(begin_pair(scene, pairs[i]));
    const State& st = scratch.states.back();
    if (st.kind == State::Kind::kHard) {
      scratch.rays.push_back(st.hard_ray);
      scratch.owner.push_back(i);
    } else if (st.kind == State::Kind::kExtent) {
      const uint32_t begin = pairs[i].count > 0 ? pairs[i].first : 0;
      const uint32_t end = pairs[i].count > 0 ? pairs[i].first + pairs[i].count : options.initial_samples;
      append_samples(pairs[i], st, i, begin, end, points_for(pairs[i], end), scratch);
    }
  }
  trace_queued(scene, scratch, pairs);
  // Round 2: pairs whose first samples disagree (some reach the light, some not) take the rest.
  for (uint32_t i = 0; i < pairs.size(); ++i) {
    const State& st = scratch.states[i];
    SoftSample& r = pairs[i].result;
    if (st.kind == State::Kind::kHard) r.samples = 1;
    if (st.kind != State::Kind::kExtent) continue;
    if (pairs[i].count > 0) {  // a run of the sequence, refined within it
      const SoftPair& p = pairs[i];
      r.samples = p.count;
      if (st.visible != 0 && st.visible != p.count && p.refine > p.count) {
        append_samples(p, st, i, p.first + p.count, p.first + p.refine, points_for(p, p.first + p.refine), scratch);
        r.samples = p.refine;
        r.refined = true;
      }
      continue;
    }
    r.samples = options.initial_samples;
    if (st.visible != 0 && st.visible != options.initial_samples && options.max_samples > options.initial_samples) {
      append_samples(pairs[i], st, i, options.initial_samples, options.max_samples,
                     points_for(pairs[i], options.max_samples), scratch);
      r.samples = options.max_samples;
      r.refined = true;
    }
  }
  trace_queued(scene, scratch, pairs);
  for (uint32_t i = 0; i < pairs.size(); ++i) {
    SoftSample& r = pairs[i].result;
    if (r.samples > 0) r.fraction = static_cast<float>(scratch.states[i].visible) / static_cast<float>(r.samples);
  }
}

SoftSample soft_visibility(const EmbreeScene& scene, const SampledLight& light, const SurfaceHit& hit, uint32_t seed,
                           const SoftOptions& options) {
  SoftPair pair{&light, &hit, seed, 0, 0, 0, {}};
  SoftScratch scratch;
  soft_visibility_batch(scene, std::span<SoftPair>(&pair, 1), options, scratch);
  return pair.result;
}

}  // namespace dhr::server
