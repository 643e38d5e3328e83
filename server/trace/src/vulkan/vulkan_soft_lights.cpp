// The lights' extents for the ray-tracing shaders' soft fields (shaders/server/light_sampler.glsl): each light as the
// Embree backend prepares it for sampling (make_sampled_light, in double), rounded to the shaders' floats.
#include "trace/soft/light_sampler.hpp"
#include "trace/vulkan/vulkan_tracer_internal.hpp"

namespace dhr::server::detail {
namespace {

uint32_t shape_code(SampledLight::Shape shape) {
  switch (shape) {
    case SampledLight::Shape::kPunctual: return shader::kVisSoftPunctual;
    case SampledLight::Shape::kSphere: return shader::kVisSoftSphere;
    case SampledLight::Shape::kSunDisk: return shader::kVisSoftSunDisk;
    case SampledLight::Shape::kRect: return shader::kVisSoftRect;
    case SampledLight::Shape::kDisk: return shader::kVisSoftDisk;
  }
  return shader::kVisSoftPunctual;
}

}  // namespace

std::vector<shader::VisSoftLight> soft_light_records(std::span<const SceneLight> lights, const glm::dvec3& origin,
                                                     uint32_t salt) {
  std::vector<shader::VisSoftLight> out;
  out.reserve(lights.size());
  for (uint32_t i = 0; i < lights.size(); ++i) {
    const SampledLight s = make_sampled_light(lights[i], origin);
    shader::VisSoftLight r{};
    r.shape = shape_code(s.shape);
    r.seed = soft_seed(0, 0, i, salt);  // SoftOptions::seed with SoftPattern::kPerLight
    r.radius = static_cast<float>(s.radius);
    r.sun_one_minus_cos = static_cast<float>(s.sun_one_minus_cos);
    const glm::vec3 centre(s.centre), direction(s.direction), half_u(s.half_u), half_v(s.half_v);
    r.centre_x = centre.x;
    r.centre_y = centre.y;
    r.centre_z = centre.z;
    r.direction_x = direction.x;
    r.direction_y = direction.y;
    r.direction_z = direction.z;
    r.half_u_x = half_u.x;
    r.half_u_y = half_u.y;
    r.half_u_z = half_u.z;
    r.half_v_x = half_v.x;
    r.half_v_y = half_v.y;
    r.half_v_z = half_v.z;
    out.push_back(r);
  }
  return out;
}

}  // namespace dhr::server::detail
