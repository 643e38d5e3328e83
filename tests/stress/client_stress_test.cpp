// The client's per-eye pipeline (G-buffer -> warp -> shading) on lavapipe under stress:
//  - the default room 1e3..1e5 m from the origin shades like the same float geometry at the origin
//    (camera-relative rendering), with visibility traced by the real Embree tracer for each placement;
//  - an extreme projection (near plane 1e-4 m, a 165 x 150 degree asymmetric FOV, 50 % guard band, the old
//    eye moved into the room so that points lie behind it): the GPU warp equals the CPU double reference;
//  - no NaN/Inf in the G-buffer, depth in [0, 1], and the same image bytes when rendered twice.
#include "client_test_helpers.hpp"
#include "metrics/visibility_synthetic.hpp"
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/offscreen_sink.hpp"
#include "render/warp_reference.hpp"
#include "stress_support.hpp"
#include "test_scenes.hpp"
#include "vulkan_test_fixture.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace dhr::stress {
namespace {

using ClientStress = vk::test::VulkanTest;
using render::EyePipeline;
using render::EyePipelineOptions;

struct Rendered {
  std::vector<uint8_t> rgba;
  std::vector<float> depth;
  std::vector<float> normals;  // 4 per pixel
  std::vector<uint32_t> mask;
  std::vector<uint32_t> status;
  render::EyeStats stats;
};

Rendered render_eye(vk::Context& ctx, const Scene& scene, const View& view, Extent extent,
                    const VisibilityInput& input, double near_plane) {
  const render::ClientScene gpu_scene(ctx, scene);
  EyePipelineOptions options;
  options.near_plane = near_plane;
  options.frames_in_flight = 1;
  options.warp_status = true;
  EyePipeline eye(ctx, gpu_scene, extent, options);
  ctx.submit_and_wait([&](VkCommandBuffer cmd) { eye.record(cmd, 0, view, input); });
  Rendered r;
  r.stats = eye.read_stats(0);
  r.rgba = render::read_rgba8(ctx, eye.output());
  r.depth = render::test::read_pixels<float>(ctx, eye.gbuffer().depth);
  r.normals = render::test::read_normals(ctx, eye.gbuffer().normal);
  r.mask = render::test::read_pixels<uint32_t>(ctx, eye.warp().mask);
  r.status = render::test::read_pixels<uint32_t>(ctx, eye.warp().status);
  return r;
}

// Non-finite normals or depth outside [0, 1] (each counted once per pixel).
uint64_t bad_gbuffer_values(const Rendered& r) {
  uint64_t bad = 0;
  for (size_t i = 0; i < r.depth.size(); ++i) {
    bool ok = std::isfinite(r.depth[i]) && r.depth[i] >= 0.0f && r.depth[i] <= 1.0f;
    for (int c = 0; c < 4; ++c) ok = ok && std::isfinite(r.normals[i * 4 + size_t(c)]);
    bad += !ok;
  }
  return bad;
}

// Pixels whose colour differs by more than `tolerance` in some channel.
uint64_t differing_pixels(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int tolerance) {
  uint64_t n = 0;
  for (size_t i = 0; i + 3 < a.size(); i += 4) {
    int worst = 0;
    for (size_t c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(a[i + c]) - int(b[i + c])));
    n += worst > tolerance;
  }
  return n;
}

View entrance_view() {
  View view;
  view.pose = render::test::look_at({0.0, 1.6, 1.35}, {-0.1, 0.5, -0.9});
  view.fov = Fov{-0.742f, 0.742f, 0.779f, -0.779f};
  return view;
}

// Shaded pixels may differ where a silhouette or shadow edge moves by rounding: 1 % of the image.
constexpr double kShadedDiffBound = 0.01;
// The same against the original (unrounded) room: silhouettes and shadow edges move by up to 4 mm at 1e5 m.
constexpr double kInputShadedDiffBound = 0.05;

TEST_F(ClientStress, FarFromTheOriginShadesLikeTheOrigin) {
  const Scene room = load_scene_or_fail(test::source_path(kDefaultScenePath));
  const Extent extent = pick(Extent{64, 48}, Extent{160, 120});
  const GuardBand guard{4, 3};
  const View view = entrance_view();
  double worst_rate = 0.0;
  uint64_t bad = 0;
  for (const double d : {1e3, 1e4, 1e5}) {
    const glm::dvec3 offset(d, 0.37 * d, -0.71 * d);
    const Scene moved = transform_scene(room, 1.0, offset);
    const Scene back = transform_scene(moved, 1.0, -offset);
    View moved_view = view;
    moved_view.pose.position += offset;
    Rendered out[3];
    const Scene* scenes[3] = {&back, &moved, &room};
    const View views[3] = {view, moved_view, view};
    for (int k = 0; k < 3; ++k) {
      VisibilityInput input;
      input.traced = Camera::with_guard_band(views[k], extent, guard);
      const VisibilityBuffer vis = trace_once(server::TracerBackend::kEmbree, *scenes[k], input.traced);
      input.buffer = &vis;
      out[k] = render_eye(ctx(), *scenes[k], views[k], extent, input, render::kDefaultNearPlane);
      bad += bad_gbuffer_values(out[k]);
      EXPECT_EQ(out[k].stats.unknown_pixels(), 0u);
    }
    const double rate = double(differing_pixels(out[0].rgba, out[1].rgba, 2)) / double(extent.width * extent.height);
    // Against the original room: includes the rounding of its vertices to float at the offset (4 mm at 1e5 m).
    const double input_rate =
        double(differing_pixels(out[2].rgba, out[1].rgba, 2)) / double(extent.width * extent.height);
    uint64_t status_diff = 0;
    for (size_t i = 0; i < out[0].status.size(); ++i) status_diff += out[0].status[i] != out[1].status[i];
    char name[64];
    std::snprintf(name, sizeof name, "client_offset_%.0e", d);
    report(name, "shaded_pixels_off_by_more_than_2_of_255", rate, kShadedDiffBound);
    report(name, "warp_status_differing_pixels", double(status_diff), 0.0);
    report(name, "input_shaded_pixels_off_by_more_than_2_of_255", input_rate, kInputShadedDiffBound);
    EXPECT_LE(input_rate, kInputShadedDiffBound) << name;
    worst_rate = std::max(worst_rate, rate);
    EXPECT_EQ(status_diff, 0u) << name;
  }
  report("client_offsets", "non_finite_gbuffer_values", double(bad), 0.0);
  EXPECT_EQ(bad, 0u);
  EXPECT_LE(worst_rate, kShadedDiffBound);
}

TEST_F(ClientStress, SameFrameTwiceGivesTheSameBytes) {
  const Scene room = load_scene_or_fail(test::source_path(kDefaultScenePath));
  const Extent extent{48, 36};
  const View view = entrance_view();
  VisibilityInput input;
  input.traced = Camera::with_guard_band(view, extent, GuardBand{4, 3});
  const VisibilityBuffer vis = trace_once(server::TracerBackend::kEmbree, room, input.traced);
  input.buffer = &vis;
  const Rendered a = render_eye(ctx(), room, view, extent, input, render::kDefaultNearPlane);
  const Rendered b = render_eye(ctx(), room, view, extent, input, render::kDefaultNearPlane);
  const uint64_t diff = differing_pixels(a.rgba, b.rgba, 0) + uint64_t(a.depth != b.depth) + uint64_t(a.mask != b.mask);
  report("determinism_client", "differing_pixels", double(diff), 0.0);
  EXPECT_EQ(diff, 0u);
}

TEST_F(ClientStress, ExtremeProjectionWarpEqualsTheCpuReference) {
  const Scene room = load_scene_or_fail(test::source_path(kDefaultScenePath));
  const Extent extent = pick(Extent{64, 48}, Extent{160, 120});
  constexpr double kNear = 1e-4;
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  View view = entrance_view();
  view.fov = Fov{float(-80 * kDeg), float(85 * kDeg), float(70 * kDeg), float(-80 * kDeg)};
  // The old eye: moved 1.2 m forward into the room and turned, so that many points are behind it.
  View old_view = view;
  old_view.pose.position += view.pose.orientation * glm::dvec3(0.1, -0.1, -1.2);
  old_view.pose = render::test::rotated(old_view.pose, 20.0, -5.0);
  const GuardBand guard{extent.width / 4, extent.height / 4};  // 50 %
  VisibilityInput input;
  input.traced = Camera::with_guard_band(old_view, extent, guard);
  const VisibilityBuffer vis = make_random_visibility(input.traced.extent.width, input.traced.extent.height, 5, 3);
  input.buffer = &vis;
  const Rendered gpu = render_eye(ctx(), room, view, extent, input, kNear);
  EXPECT_EQ(bad_gbuffer_values(gpu), 0u);

  render::WarpInput cpu_in;
  cpu_in.depth = gpu.depth;
  cpu_in.display = render::display_camera(view, extent);
  cpu_in.sources[0].traced = input.traced;
  cpu_in.near_plane = kNear;
  cpu_in.sources[0].visibility = &vis;
  const render::WarpResult cpu = render::warp_reference(cpu_in);
  uint64_t judged = 0, mismatched = 0;
  for (size_t i = 0; i < cpu.masks.size(); ++i) {
    if (cpu.margin[i] < 2e-3) continue;  // too close to flipping for float (warp_reference.hpp)
    ++judged;
    mismatched += cpu.masks[i] != gpu.mask[i] || uint32_t(cpu.status[i]) != gpu.status[i];
  }
  const double excluded = 1.0 - double(judged) / double(cpu.masks.size());
  report("client_extreme_projection", "warp_mismatched_pixels", double(mismatched), 0.0);
  report("client_extreme_projection", "pixels_within_flip_margin", excluded, 0.05);
  EXPECT_EQ(mismatched, 0u);
  EXPECT_LE(excluded, 0.05);
  EXPECT_GT(cpu.counts[render::WarpStatus::kBehind], 0u);
  EXPECT_GT(cpu.counts[render::WarpStatus::kKnown], 0u);
}

}  // namespace
}  // namespace dhr::stress
