#include "trace/stats_json.hpp"

namespace dhr::server {

nlohmann::ordered_json to_json(const TraceStats& s) {
  return {{"pixels", s.pixels},
          {"background_pixels", s.background_pixels},
          {"primary_rays", s.primary_rays},
          {"shadow_rays", s.shadow_rays},
          {"skipped_backfacing", s.skipped_backfacing},
          {"skipped_out_of_range", s.skipped_out_of_range},
          {"skipped_culled_light", s.skipped_culled_light},
          {"lights_culled", s.lights_culled},
          {"lights_unrequested", s.lights_unrequested},
          {"soft_pairs", s.soft_pairs},
          {"soft_contributing_pairs", s.soft_contributing_pairs},
          {"soft_refined_pairs", s.soft_refined_pairs},
          {"soft_shadow_rays", s.soft_shadow_rays},
          {"soft_rays_per_pair", s.soft_rays_per_pair()},
          {"soft_refined_share", s.soft_refined_share()},
          {"reused_pixels", s.reused_pixels},
          {"reused_pairs", s.reused_pairs},
          {"refreshed_pixels", s.refreshed_pixels},
          {"trace_ms", s.trace_ms},
          {"gpu_ms", s.gpu_ms}};
}

nlohmann::ordered_json to_json(const AccelStats& s) {
  return {{"build_ms", s.build_ms},
          {"bytes", s.bytes},
          {"triangles", s.triangles},
          {"blas_count", s.blas_count},
          {"instance_count", s.instance_count}};
}

nlohmann::ordered_json to_json(const SkipOptions& s) {
  return {{"backfacing", s.backfacing}, {"out_of_range", s.out_of_range}, {"cull_lights", s.cull_lights}};
}

}  // namespace dhr::server
