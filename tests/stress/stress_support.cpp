#include "stress_support.hpp"

#include "scene/camera_bookmarks.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <sys/resource.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace dhr::stress {

bool long_mode() {
  const char* env = std::getenv("DHR_STRESS_LONG");
  return env != nullptr && *env != '\0' && std::string(env) != "0";
}

void report(const std::string& stress_case, const std::string& metric, double worst, double bound) {
  std::printf("[stress] %s %s: worst=%.6g bound=%.6g%s\n", stress_case.c_str(), metric.c_str(), worst, bound,
              long_mode() ? " (long)" : "");
  std::fflush(stdout);
}

Scene transform_scene(const Scene& scene, double scale, const glm::dvec3& offset) {
  Scene out = scene;
  const glm::dmat4 T = glm::scale(glm::translate(glm::dmat4(1.0), offset), glm::dvec3(scale));
  out.bounds = SceneBounds{};
  for (SceneMesh& m : out.meshes) {
    for (glm::vec3& p : m.positions) {
      p = glm::vec3(glm::dvec3(p) * scale + offset);
      out.bounds.extend(p);
    }
    m.T_world_local = T * m.T_world_local;
  }
  for (SceneLight& l : out.lights) {
    l.position = glm::vec3(glm::dvec3(l.position) * scale + offset);
    l.range = static_cast<float>(double(l.range) * scale);
    // Keep the irradiance at scaled distances: visibility bits do not depend on it, shading does.
    if (l.type != SceneLight::Type::kDirectional) l.intensity = static_cast<float>(double(l.intensity) * scale * scale);
  }
  return out;
}

Camera transform_camera(const Camera& camera, double scale, const glm::dvec3& offset) {
  Camera out = camera;
  out.T_world_eye.position = camera.T_world_eye.position * scale + offset;
  return out;
}

uint64_t total_bits(const VisibilityBuffer& v) { return uint64_t(v.pixel_count()) * v.light_count; }

uint64_t differing_bits(const VisibilityBuffer& a, const VisibilityBuffer& b) {
  if (a.width != b.width || a.height != b.height || a.light_count != b.light_count) return UINT64_MAX;
  uint64_t n = 0;
  for (size_t i = 0; i < a.pixel_count(); ++i) n += uint64_t(std::popcount(a.mask_at(i) ^ b.mask_at(i)));
  return n;
}

uint64_t differing_bits_off_edges(const VisibilityBuffer& a, const VisibilityBuffer& b) {
  if (a.width != b.width || a.height != b.height || a.light_count != b.light_count) return UINT64_MAX;
  const int w = int(a.width), h = int(a.height);
  uint64_t n = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const uint32_t diff = a.get(uint32_t(x), uint32_t(y)) ^ b.get(uint32_t(x), uint32_t(y));
      if (diff == 0) continue;
      uint32_t edge = 0;  // bits that change somewhere in the reference's 3x3 neighbourhood
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = std::clamp(x + dx, 0, w - 1), ny = std::clamp(y + dy, 0, h - 1);
          edge |= a.get(uint32_t(nx), uint32_t(ny)) ^ a.get(uint32_t(x), uint32_t(y));
        }
      }
      n += uint64_t(std::popcount(diff & ~edge));
    }
  }
  return n;
}

server::TracerOptions embree_options(server::SkipOptions skip) {
  server::TracerOptions o;
  o.skip = skip;
  o.threads = 2;
  return o;
}

server::TracerOptions vulkan_options(server::SkipOptions skip) {
  server::TracerOptions o;
  o.skip = skip;
  return o;
}

VisibilityBuffer trace_once(server::TracerBackend backend, const Scene& scene, const Camera& camera,
                            server::SkipOptions skip, server::TraceStats* out_stats) {
  const server::TracerOptions options =
      backend == server::TracerBackend::kEmbree ? embree_options(skip) : vulkan_options(skip);
  auto tracer = server::create_tracer(backend, scene, options);
  VisibilityBuffer out;
  server::TraceStats stats;
  tracer->trace(camera, out, stats);
  if (out_stats != nullptr) *out_stats = stats;
  return out;
}

const char* backend_label(server::TracerBackend backend) {
  return backend == server::TracerBackend::kVulkan ? "vulkan" : "embree";
}

double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // KiB on Linux
}

}  // namespace dhr::stress
