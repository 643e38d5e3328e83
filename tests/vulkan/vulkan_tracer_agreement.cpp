#include "vulkan_tracer_agreement.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <algorithm>
#include <cstdio>

#include "trace/ray_offset.hpp"

namespace dhr::server::tracer_test {
namespace {

// The reference's primary hit per pixel (same rays as the Embree tracer's).
struct PixelHit {
  bool hit = false;
  uint32_t mesh = 0;
  double depth = 0.0;
};

std::vector<PixelHit> reference_hits(const EmbreeTracer& embree, const Camera& camera) {
  const EmbreeScene& scene = embree.embree_scene();
  const glm::vec3 eye = scene.to_relative(camera.T_world_eye.position);
  const glm::dmat3 R = glm::mat3_cast(glm::normalize(camera.T_world_eye.orientation));
  std::vector<PixelHit> hits(size_t{camera.extent.width} * camera.extent.height);
  for (uint32_t y = 0; y < camera.extent.height; ++y) {
    for (uint32_t x = 0; x < camera.extent.width; ++x) {
      const glm::vec3 dir(glm::normalize(R * camera.eye_ray(x + 0.5, y + 0.5)));
      // Primary rays start at the client's near plane (kClipNearPlane along the view axis).
      const float tnear = static_cast<float>(kClipNearPlane / glm::dot(glm::dvec3(dir), R * glm::dvec3(0, 0, -1)));
      const auto hit = scene.intersect(eye, dir, tnear);
      PixelHit& h = hits[size_t{y} * camera.extent.width + x];
      if (!hit) continue;
      h.hit = true;
      h.mesh = hit->mesh;
      h.depth = glm::length(glm::dvec3(hit->position) - glm::dvec3(eye));
    }
  }
  return hits;
}

// Differing pixel-light bits, and those not explained by a silhouette or a shadow boundary within one
// pixel. A silhouette pixel differs from a 4-neighbour in hit/miss, mesh, or depth (> 2% jump); a bit is
// at a shadow boundary when the reference has the other value of that bit in the 3x3 neighbourhood.
struct Agreement {
  uint64_t bits = 0;
  uint64_t differing = 0;
  uint64_t unexplained = 0;
  uint64_t differing_pixels = 0;
  struct Pixel {
    int x = 0, y = 0;
    uint32_t bits = 0;  // its unexplained bits
  };
  std::vector<Pixel> unexplained_pixels;  // in raster order
  double rate() const { return bits ? double(differing) / double(bits) : 0.0; }
};

std::vector<uint8_t> silhouettes(const std::vector<PixelHit>& hits, int w, int h) {
  auto at = [&](int x, int y) -> const PixelHit& { return hits[size_t(y) * size_t(w) + size_t(x)]; };
  std::vector<uint8_t> edge(size_t(w) * size_t(h), 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const PixelHit& p = at(x, y);
      const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
        const PixelHit& q = at(nx[k], ny[k]);
        if (p.hit != q.hit || (p.hit && (p.mesh != q.mesh || std::abs(p.depth - q.depth) >
                                                                  0.02 * std::min(p.depth, q.depth))))
          edge[size_t(y) * size_t(w) + size_t(x)] = 1;
      }
    }
  }
  return edge;
}

Agreement compare(const VisibilityBuffer& ref, const VisibilityBuffer& got, const std::vector<PixelHit>& hits) {
  Agreement a;
  const int w = int(ref.width), h = int(ref.height);
  a.bits = uint64_t(ref.pixel_count()) * ref.light_count;
  const std::vector<uint8_t> edge = silhouettes(hits, w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const uint32_t diff = ref.get(uint32_t(x), uint32_t(y)) ^ got.get(uint32_t(x), uint32_t(y));
      if (!diff) continue;
      ++a.differing_pixels;
      a.differing += uint64_t(std::popcount(diff));
      bool near_edge = false;
      uint32_t boundary_bits = 0;  // bits that change somewhere in the reference's 3x3 neighbourhood
      const uint32_t centre = ref.get(uint32_t(x), uint32_t(y));
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          near_edge = near_edge || edge[size_t(qy) * size_t(w) + size_t(qx)];
          boundary_bits |= centre ^ ref.get(uint32_t(qx), uint32_t(qy));
        }
      }
      if (near_edge) continue;
      const uint32_t unexplained = diff & ~boundary_bits;
      if (!unexplained) continue;
      a.unexplained += uint64_t(std::popcount(unexplained));
      a.unexplained_pixels.push_back({x, y, unexplained});
    }
  }
  return a;
}

// Where the reference's shadow ray from pixel (x, y) toward a point or spot light first meets a front face
// (EmbreeScene::intersect culls single-sided back faces; shadow rays see every face). Empty without a primary hit.
struct ShadowRayOccluder {
  bool primary_hit = false;
  bool met = false;       // a front face before the light
  float at = 0.0f;        // where, from the ray's origin (m)
  float distance = 0.0f;  // the light's distance from the ray's origin (m)
  uint32_t mesh = 0, triangle = 0;
  float barycentrics[3] = {0.0f, 0.0f, 0.0f};
};

ShadowRayOccluder reference_occluder(const EmbreeScene& scene, const Camera& camera, const SceneLight& light, int x,
                                     int y) {
  ShadowRayOccluder r;
  const glm::vec3 eye = scene.to_relative(camera.T_world_eye.position);
  const glm::dmat3 R = glm::mat3_cast(glm::normalize(camera.T_world_eye.orientation));
  const glm::vec3 dir(glm::normalize(R * camera.eye_ray(x + 0.5, y + 0.5)));
  const float tnear = static_cast<float>(kClipNearPlane / glm::dot(glm::dvec3(dir), R * glm::dvec3(0, 0, -1)));
  const auto hit = scene.intersect(eye, dir, tnear);
  if (!hit) return r;
  r.primary_hit = true;
  const glm::vec3 lp = scene.to_relative(glm::dvec3(light.position));
  const glm::vec3 n = glm::dot(hit->geometric_normal, lp - hit->position) >= 0.0f ? hit->geometric_normal
                                                                                 : -hit->geometric_normal;
  const glm::vec3 o = offset_ray_origin(hit->position, n, scene.ray_offset());
  r.distance = glm::length(lp - o);
  const auto s = scene.intersect(o, (lp - o) / r.distance);
  r.at = s ? glm::length(s->position - o) : 0.0f;
  if (!s || r.at >= r.distance) return r;
  r.met = true;
  r.mesh = s->mesh;
  r.triangle = s->triangle;
  r.barycentrics[0] = 1.0f - s->u - s->v;
  r.barycentrics[1] = s->u;
  r.barycentrics[2] = s->v;
  return r;
}

bool is_point_or_spot(const SceneLight& light) {
  return light.type == SceneLight::Type::kPoint || light.type == SceneLight::Type::kSpot;
}

}  // namespace

// A light on a surface: the reference's occluder lies within kAtTheLight of the light's distance. Both tracers end
// shadow rays at the same distance (kShadowTfarScale), and whether a triangle that close counts is decided by
// each implementation's intersection arithmetic at that end: either answer stands. (Measured on an NVIDIA H100:
// light 30 of MaskWidthsFollowTheLightCount, placed on a box's face, met it at 2.4964 of 2.4964 m.)
constexpr float kAtTheLight = 1e-4f;  // relative to the light's distance: 10x the rays' end (1 - kShadowTfarScale)

bool occluder_at_the_light(const EmbreeScene& scene, const Camera& camera, const SceneLight& light, int x, int y) {
  if (!is_point_or_spot(light)) return false;
  const ShadowRayOccluder r = reference_occluder(scene, camera, light, x, y);
  return r.met && r.distance - r.at <= kAtTheLight * r.distance;
}

// For a failure message: where the reference's shadow ray from pixel (x, y) to each point or spot light in `bits`
// first meets a front face, and how close to that triangle's edges (its smallest barycentric). A ray through an
// edge or a vertex may go either way in another implementation: Vulkan asks for a watertight test but does not
// require one.
std::string describe_shadow_rays(const EmbreeTracer& embree, const Camera& camera, const std::vector<SceneLight>& lights,
                                 int x, int y, uint32_t bits) {
  std::string out;
  for (uint32_t li = 0; li < lights.size() && li < 32; ++li) {
    if (((bits >> li) & 1u) == 0) continue;
    char text[256];
    if (!is_point_or_spot(lights[li])) {
      std::snprintf(text, sizeof text, "; light %u: not a point or spot light, not described", li);
      out += text;
      continue;
    }
    const ShadowRayOccluder r = reference_occluder(embree.embree_scene(), camera, lights[li], x, y);
    if (!r.primary_hit) return "; no primary hit in the reference";
    if (!r.met) {
      std::snprintf(text, sizeof text, "; light %u: no front face before the light (%.4f m; a back face may occlude)",
                    li, double{r.distance});
    } else {
      const float* b = r.barycentrics;
      std::snprintf(text, sizeof text,
                    "; light %u: the shadow ray meets mesh %u triangle %u at %.6f of %.6f m, barycentrics (%.2e, "
                    "%.2e, %.2e), smallest %.2e",
                    li, r.mesh, r.triangle, double{r.at}, double{r.distance}, double{b[0]}, double{b[1]},
                    double{b[2]}, double{std::min({b[0], b[1], b[2]})});
    }
    out += text;
  }
  return out;
}

std::vector<uint8_t> near_silhouette(const EmbreeTracer& embree, const Camera& camera) {
  const int w = int(camera.extent.width), h = int(camera.extent.height);
  const std::vector<uint8_t> edge = silhouettes(reference_hits(embree, camera), w, h);
  std::vector<uint8_t> near(edge.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx >= 0 && qy >= 0 && qx < w && qy < h && edge[size_t(qy) * size_t(w) + size_t(qx)])
            near[size_t(y) * size_t(w) + size_t(x)] = 1;
        }
  return near;
}

void expect_agreement(const Scene& scene, const std::vector<Camera>& cameras, const TracerOptions& vk_options,
                      const TracerOptions& embree_options, const VulkanTracerConfig& config,
                      const std::vector<double>& scene_times) {
  EmbreeTracer embree(scene, embree_options);
  VulkanTracer vulkan(scene, vk_options, config);
  uint64_t bits = 0, differing = 0;
  const std::vector<double> times = scene_times.empty() ? std::vector<double>{-1.0} : scene_times;
  for (const double t : times) {
  if (t >= 0.0) {
    embree.set_scene_time(t);
    vulkan.set_scene_time(t);
    std::printf("[ agreement ] scene time %.3f s\n", t);
  }
  for (size_t c = 0; c < cameras.size(); ++c) {
    VisibilityBuffer ref, got;
    TraceStats ref_stats, got_stats;
    embree.trace(cameras[c], ref, ref_stats);
    vulkan.trace(cameras[c], got, got_stats);
    ASSERT_EQ(got.width, ref.width);
    ASSERT_EQ(got.height, ref.height);
    ASSERT_EQ(got.mask_bits, ref.mask_bits);
    Agreement a = compare(ref, got, reference_hits(embree, cameras[c]));
    // Bits of a light that sits on a surface: explained (occluder_at_the_light), counted apart.
    uint64_t at_light = 0;
    std::vector<Agreement::Pixel> left;
    for (Agreement::Pixel p : a.unexplained_pixels) {
      for (uint32_t li = 0; li < scene.lights.size() && li < 32; ++li)
        if (((p.bits >> li) & 1u) && occluder_at_the_light(embree.embree_scene(), cameras[c], scene.lights[li], p.x, p.y)) {
          p.bits &= ~(1u << li);
          ++at_light;
        }
      if (p.bits) left.push_back(p);
    }
    a.unexplained -= at_light;
    if (at_light) std::printf("[ agreement ] camera %zu: %llu differing bits of lights on a surface\n", c,
                              static_cast<unsigned long long>(at_light));
    std::printf("[ agreement ] camera %zu %ux%u, %u lights: %llu of %llu bits differ (%.4f%%), %llu pixels, "
                "%llu unexplained; vulkan %.1f ms (gpu %.1f ms), embree %.1f ms\n",
                c, ref.width, ref.height, ref.light_count, static_cast<unsigned long long>(a.differing),
                static_cast<unsigned long long>(a.bits), 100.0 * a.rate(),
                static_cast<unsigned long long>(a.differing_pixels), static_cast<unsigned long long>(a.unexplained),
                got_stats.trace_ms, got_stats.gpu_ms, ref_stats.trace_ms);
    std::string first;
    if (!left.empty()) {
      const auto [x, y, pixel_bits] = left[0];
      char text[128];
      std::snprintf(text, sizeof text, "pixel (%d, %d): reference 0x%x, vulkan 0x%x", x, y,
                    ref.get(uint32_t(x), uint32_t(y)), got.get(uint32_t(x), uint32_t(y)));
      first = text + describe_shadow_rays(embree, cameras[c], scene.lights, x, y, pixel_bits);
    }
    EXPECT_EQ(a.unexplained, 0u) << "camera " << c << ": first at " << first;
    EXPECT_LT(a.rate(), 0.001) << "camera " << c;
    // Statistics: one primary ray per pixel; every hit pixel-light pair traced or skipped for a reason.
    EXPECT_EQ(got_stats.pixels, ref_stats.pixels);
    EXPECT_EQ(got_stats.primary_rays, got_stats.pixels);
    EXPECT_EQ(got_stats.lights_culled, ref_stats.lights_culled);
    const uint64_t hit = got_stats.pixels - got_stats.background_pixels;
    EXPECT_EQ(got_stats.shadow_rays + got_stats.skipped_backfacing + got_stats.skipped_out_of_range +
                  got_stats.skipped_culled_light,
              hit * vulkan.light_count());  // fields: the lights, or the slots they share
    EXPECT_NEAR(double(got_stats.background_pixels), double(ref_stats.background_pixels), 0.01 * got_stats.pixels);
    EXPECT_NEAR(double(got_stats.shadow_rays), double(ref_stats.shadow_rays),
                0.01 * double(ref_stats.shadow_rays) + 4.0);
    EXPECT_GT(got_stats.trace_ms, 0.0);
    bits += a.bits;
    differing += a.differing;
  }
  }
  EXPECT_EQ(vulkan.validation_error_count(), 0u);
  if (bits) std::printf("[ agreement ] all cameras: %.4f%% of bits differ\n", 100.0 * double(differing) / double(bits));
}


}  // namespace dhr::server::tracer_test
