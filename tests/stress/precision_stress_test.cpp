// Scenes far from the world origin (1e3, 1e4, 1e5 m) and scaled (1e-4 .. 1e4): the real tracers (Embree,
// Vulkan on lavapipe at tiny sizes) against the same scene at the origin / at scale 1.
//
// Two errors are reported per offset. "tracer": against the offset scene's own float geometry moved back
// to the origin exactly (a float near 1e5 minus 1e5 is exact), so only the tracer's arithmetic differs.
// "input": against the original scene; this includes the rounding of the scene's float vertices at the
// offset (8 mm at 1e5 m), which no tracer can undo.
#include "trace/embree/embree_tracer.hpp"
#include "stress_support.hpp"
#include "test_scenes.hpp"
#include "trace/vulkan/vulkan_tracer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace dhr::stress {
namespace {

using server::EmbreeTracer;
using server::VulkanTracer;

struct Errors {
  uint64_t bits = 0;
  uint64_t differing = 0;
  uint64_t off_edge = 0;
  uint64_t lit_only_moved = 0;  // differing bits lit in the moved/scaled scene and dark in the reference
  double rate() const { return bits ? double(differing) / double(bits) : 0.0; }
};

bool all_finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

template <typename Tracer>
Errors compare_scenes(const Scene& reference, const Scene& moved, const std::vector<Camera>& ref_cameras,
                      double scale, const glm::dvec3& offset, const server::TracerOptions& options) {
  Tracer ref_tracer(reference, options);
  server::TracerOptions moved_options = options;
  moved_options.primary_near *= scale;  // the client's near plane, drawn at the scene's scale
  Tracer moved_tracer(moved, moved_options);
  Errors e;
  for (const Camera& camera : ref_cameras) {
    const Camera moved_camera = transform_camera(camera, scale, offset);
    EXPECT_TRUE(all_finite(moved_camera.view_projection(1e-3)));
    VisibilityBuffer a, b;
    server::TraceStats sa, sb;
    ref_tracer.trace(camera, a, sa);
    moved_tracer.trace(moved_camera, b, sb);
    e.bits += total_bits(a);
    e.differing += differing_bits(a, b);
    e.off_edge += differing_bits_off_edges(a, b);
    for (size_t i = 0; i < a.pixel_count(); ++i) e.lit_only_moved += uint64_t(std::popcount(b.mask_at(i) & ~a.mask_at(i)));
  }
  return e;
}

Scene default_room() { return load_scene_or_fail(test::source_path(kDefaultScenePath)); }

std::vector<Camera> cameras_for(const std::string& path, Extent eye, size_t max_count) {
  std::vector<Camera> cameras = bookmark_cameras(path, eye);
  if (cameras.size() > max_count) cameras.resize(max_count);
  return cameras;
}

// Bounds (fractions of all pixel-light bits). The tracer bound: both tracers trace relative to a local
// origin, so the arithmetic is the same up to last-bit rounding of the re-centring.
constexpr double kTracerRateBound = 1e-3;
// The input bound: vertices and lights rounded to float at the offset (ULP 8 mm at 1e5 m) move shadow
// edges and silhouettes by up to a few millimetres: a few pixels' worth at these sizes.
constexpr double kInputRateBound = 0.02;

template <typename Tracer>
void run_offsets(const char* backend, Extent eye, size_t max_cameras, const std::vector<double>& offsets,
                 const server::TracerOptions& options) {
  const std::string path = test::source_path(kDefaultScenePath);
  const Scene scene = default_room();
  const std::vector<Camera> cameras = cameras_for(path, eye, max_cameras);
  ASSERT_FALSE(cameras.empty());
  for (const double d : offsets) {
    // A diagonal offset so that every axis carries a large coordinate.
    const glm::dvec3 offset = glm::dvec3(d, 0.37 * d, -0.71 * d);
    const Scene moved = transform_scene(scene, 1.0, offset);
    const Scene back = transform_scene(moved, 1.0, -offset);  // exact: the moved floats shifted back
    const Errors tracer = compare_scenes<Tracer>(back, moved, cameras, 1.0, offset, options);
    const Errors input = compare_scenes<Tracer>(scene, moved, cameras, 1.0, offset, options);
    char name[96];
    std::snprintf(name, sizeof name, "offset_%s_%.0e", backend, d);
    report(name, "tracer_bit_error_rate", tracer.rate(), kTracerRateBound);
    report(name, "tracer_bits_off_edges", double(tracer.off_edge), 0.0);
    report(name, "input_bit_error_rate", input.rate(), kInputRateBound);
    EXPECT_LE(tracer.rate(), kTracerRateBound) << name;
    EXPECT_EQ(tracer.off_edge, 0u) << name;
    EXPECT_LE(input.rate(), kInputRateBound) << name;
  }
}

TEST(StressPrecision, EmbreeFarFromTheOriginMatchesTheOrigin) {
  run_offsets<EmbreeTracer>("embree", pick(Extent{64, 48}, Extent{192, 144}), pick<size_t>(3, 100),
                            {1e3, 1e4, 1e5}, embree_options());
}

TEST(StressPrecision, VulkanFarFromTheOriginMatchesTheOrigin) {
  run_offsets<VulkanTracer>("vulkan", pick(Extent{32, 24}, Extent{96, 72}), pick<size_t>(1, 100), {1e3, 1e4, 1e5},
                            vulkan_options());
}

// Scales: shadow edges and silhouettes may move by float rounding of the scaled vertices (relative 6e-8),
// far below a pixel; nothing else may change. The shadow-ray offset's near-origin terms scale with the scene
// (server/trace/include/trace/ray_offset.hpp, ray_offset_scale), so a 5 mm room gets a 5 mm room's offset: measured 0 differing
// bits at every scale, default and long mode. (With the fixed 1/65536 m term, 1e-3 differed in 0.2 % of
// its bits, some off shadow edges, and needed a 5e-3 bound.) Bound: a few rounding-moved edge bits.
constexpr double kScaleRateBound = 1e-4;
constexpr double kScaleOffEdgeRateBound = 0.0;

template <typename Tracer>
void run_scales(const char* backend, Extent eye, size_t max_cameras, const std::vector<double>& scales,
                const server::TracerOptions& options) {
  const std::string path = test::source_path(kDefaultScenePath);
  const Scene scene = default_room();
  const std::vector<Camera> cameras = cameras_for(path, eye, max_cameras);
  ASSERT_FALSE(cameras.empty());
  for (const double s : scales) {
    const Scene scaled = transform_scene(scene, s, glm::dvec3(0.0));
    const Errors e = compare_scenes<Tracer>(scene, scaled, cameras, s, glm::dvec3(0.0), options);
    char name[96];
    std::snprintf(name, sizeof name, "scale_%s_%.0e", backend, s);
    const double off_edge_rate = e.bits ? double(e.off_edge) / double(e.bits) : 0.0;
    report(name, "bit_error_rate", e.rate(), kScaleRateBound);
    std::printf("[stress] %s: %llu of %llu differing bits are lit only in the scaled scene\n", name,
                static_cast<unsigned long long>(e.lit_only_moved), static_cast<unsigned long long>(e.differing));
    report(name, "off_edge_bit_error_rate", off_edge_rate, kScaleOffEdgeRateBound);
    EXPECT_LE(e.rate(), kScaleRateBound) << name;
    EXPECT_LE(off_edge_rate, kScaleOffEdgeRateBound) << name;
  }
}

TEST(StressPrecision, EmbreeScaledScenesMatchScaleOne) {
  run_scales<EmbreeTracer>("embree", pick(Extent{64, 48}, Extent{192, 144}), pick<size_t>(3, 100),
                           {1e-4, 1e-3, 1e-2, 1e-1, 10.0, 100.0, 1e3, 1e4}, embree_options());
}

TEST(StressPrecision, VulkanScaledScenesMatchScaleOne) {
  run_scales<VulkanTracer>("vulkan", pick(Extent{32, 24}, Extent{96, 72}), pick<size_t>(1, 100), {1e-3, 1e-2, 1e3},
                           vulkan_options());
}

}  // namespace
}  // namespace dhr::stress
