#include "trace/soft/soft_visibility.hpp"

#include "trace/embree/embree_trace_tile.hpp"
#include "trace/ray_offset.hpp"

#include <glm/geometric.hpp>

namespace dhr::server {
namespace {

bool ray_reaches(const EmbreeScene& scene, RTCRay ray) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  rtcOccluded1(scene.handle(), &context, &ray);
  return ray.tfar >= 0.0f;  // Embree sets tfar = -inf when occluded
}

}  // namespace

std::optional<std::string> validate_soft_options(const SoftOptions& o) {
  if (o.initial_samples == 0) return "soft visibility: initial samples must be at least 1";
  if (o.max_samples < o.initial_samples) return "soft visibility: max samples below initial samples";
  if (o.max_samples > kMaxSoftSamples)
    return "soft visibility: more than " + std::to_string(kMaxSoftSamples) + " samples";
  return std::nullopt;
}

SoftSample soft_visibility(const EmbreeScene& scene, const SampledLight& light, const SurfaceHit& hit, uint32_t seed,
                           const SoftOptions& options) {
  SoftSample out;
  const LightSample centre = sample_light(light.packed, hit.position, hit.shading_normal);
  out.test = centre.test;
  if (centre.test != LightTest::kContributes) return out;

  if (light.shape == SampledLight::Shape::kPunctual) {
    RTCRay ray;
    detail::make_shadow_ray(light.packed, hit, centre, scene.ray_offset(), ray);
    out.rays = out.samples = 1;
    out.fraction = ray_reaches(scene, ray) ? 1.0f : 0.0f;
    return out;
  }

  // The hard tracer's origin: leave from the side of the surface the light's centre is on.
  const glm::vec3 n = glm::dot(hit.geometric_normal, centre.l) >= 0.0f ? hit.geometric_normal : -hit.geometric_normal;
  const glm::vec3 origin = offset_ray_origin(hit.position, n, scene.ray_offset());
  const std::optional<LightView> view = LightView::create(light, origin);
  if (!view) {
    if (light.one_sided()) return out;  // behind (or in the plane of) a one-sided emitter: nothing arrives
    // Inside a sphere light: no cap to sample; the hard ray toward its centre decides.
    RTCRay ray;
    detail::make_shadow_ray(light.packed, hit, centre, scene.ray_offset(), ray);
    out.rays = out.samples = 1;
    out.fraction = ray_reaches(scene, ray) ? 1.0f : 0.0f;
    return out;
  }

  uint32_t visible = 0;
  auto take = [&](uint32_t begin, uint32_t end) {
    for (uint32_t i = begin; i < end; ++i) {
      const SampleRay s = view->sample(sample_2d(i, seed));
      if (!(glm::dot(n, s.dir) > 0.0f)) continue;  // below the horizon: the surface itself hides it
      ++out.rays;
      if (ray_reaches(scene, make_rtc_ray(origin, s.dir, s.tfar))) ++visible;
    }
  };
  take(0, options.initial_samples);
  out.samples = options.initial_samples;
  if (visible != 0 && visible != options.initial_samples && options.max_samples > options.initial_samples) {
    take(options.initial_samples, options.max_samples);
    out.samples = options.max_samples;
    out.refined = true;
  }
  out.fraction = static_cast<float>(visible) / static_cast<float>(out.samples);
  return out;
}

}  // namespace dhr::server
