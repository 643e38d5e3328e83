#include "bare_embree.hpp"

#include "bench_timing.hpp"

#include "trace/embree/embree_trace_tile.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <ctime>
#include <limits>
#include <thread>

namespace dhr::bench {
namespace {

// Runs fn(begin, end, worker) over [0, count) in chunks claimed through an atomic counter (as the tracer
// hands out tiles), on `threads` threads including the caller's.
template <typename Fn>
void parallel_chunks(size_t count, size_t chunk, unsigned threads, Fn&& fn) {
  const unsigned workers = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>((count + chunk - 1) / chunk)));
  std::atomic<size_t> next{0};
  auto work = [&](unsigned worker) {
    for (size_t begin = next.fetch_add(chunk); begin < count; begin = next.fetch_add(chunk))
      fn(begin, std::min(count, begin + chunk), worker);
  };
  std::vector<std::thread> pool;
  for (unsigned w = 1; w < workers; ++w) pool.emplace_back(work, w);
  work(0);
  for (std::thread& t : pool) t.join();
}

void reset_primary(RTCRayHit& rh) {
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace

double process_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

CapturedRays capture_rays(const server::EmbreeScene& scene, const std::vector<SceneLight>& lights,
                          const Camera& camera, const server::SkipOptions& skip, unsigned threads) {
  const server::detail::FrameSetup frame = server::detail::make_frame_setup(scene, lights, camera, skip);
  const uint32_t width = camera.extent.width, height = camera.extent.height;
  CapturedRays out;
  out.primary.resize(static_cast<size_t>(width) * height);
  // Rows in order: each row's shadow rays go to its own list, joined afterwards (same order for any threads).
  std::vector<std::vector<RTCRay>> row_shadow(height);
  std::vector<uint64_t> row_hits(height, 0);
  parallel_chunks(height, 1, threads, [&](size_t y0, size_t y1, unsigned /*worker*/) {
    server::TraceStats counts;  // skip counters: not reported (the tracer's own statistics are)
    for (size_t y = y0; y < y1; ++y) {
      for (uint32_t x = 0; x < width; ++x) {
        const glm::vec3 dir = server::detail::primary_direction(frame, x, static_cast<uint32_t>(y));
        RTCRayHit& rh = out.primary[y * width + x];
        rh = RTCRayHit{};
        rh.ray = server::make_rtc_ray(frame.eye, dir, std::numeric_limits<float>::infinity());
        rh.ray.tnear = server::detail::primary_tnear(frame, dir);
        reset_primary(rh);
        const std::optional<server::SurfaceHit> hit = scene.intersect(frame.eye, dir, rh.ray.tnear);
        if (!hit) continue;
        ++row_hits[y];
        for (uint32_t li : frame.active_lights) {
          RTCRay ray;
          bool contributes = false;
          if (server::detail::shadow_ray_for(frame, frame.lights[li], *hit, counts, ray, contributes))
            row_shadow[y].push_back(ray);
        }
      }
    }
  });
  size_t total = 0;
  for (const auto& r : row_shadow) total += r.size();
  out.shadow.reserve(total);
  for (uint32_t y = 0; y < height; ++y) {
    out.shadow.insert(out.shadow.end(), row_shadow[y].begin(), row_shadow[y].end());
    std::vector<RTCRay>().swap(row_shadow[y]);
    out.primary_hits += row_hits[y];
  }
  out.shadow_tfar.reserve(total);
  for (const RTCRay& r : out.shadow) out.shadow_tfar.push_back(r.tfar);
  return out;
}

BareLoopResult run_bare_loop(RTCScene scene, CapturedRays& rays, unsigned threads) {
  for (RTCRayHit& rh : rays.primary) reset_primary(rh);
  for (size_t i = 0; i < rays.shadow.size(); ++i) rays.shadow[i].tfar = rays.shadow_tfar[i];
  constexpr size_t kChunk = 4096;
  BareLoopResult result;
  const double cpu0 = process_cpu_ms();
  auto t0 = std::chrono::steady_clock::now();
  parallel_chunks(rays.primary.size(), kChunk, threads, [&](size_t begin, size_t end, unsigned /*worker*/) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = begin; i < end; ++i) rtcIntersect1(scene, &context, &rays.primary[i]);
  });
  result.primary_ms = ms_since(t0);

  t0 = std::chrono::steady_clock::now();
  parallel_chunks(rays.shadow.size(), kChunk, threads, [&](size_t begin, size_t end, unsigned /*worker*/) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = begin; i < end; ++i) rtcOccluded1(scene, &context, &rays.shadow[i]);
  });
  result.shadow_ms = ms_since(t0);
  result.cpu_ms = process_cpu_ms() - cpu0;

  for (const RTCRayHit& rh : rays.primary) result.primary_hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  for (const RTCRay& r : rays.shadow) result.occluded += r.tfar < 0.0f;
  return result;
}

}  // namespace dhr::bench
