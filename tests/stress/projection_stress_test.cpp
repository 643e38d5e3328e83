// Projection extremes on the CPU (double): near planes 1e-4..1 m, fields of view 10..170 degrees, symmetric
// and asymmetric, guard bands up to 50 % of the image, cameras at the origin and 1e5 m away. Every matrix and
// every projected value must be finite, the reversed-Z matrix must agree with reproject() and with the
// pixel the point was made from, and a guard band must shift pixels by exactly its half-width.
// Reprojection of points behind the old eye, at its position and on its image edges gives the documented
// statuses, never NaN.
#include "stress_support.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace dhr::stress {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

bool finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

struct FovCase {
  double left_deg, right_deg, up_deg, down_deg;
};

std::vector<FovCase> fov_cases() {
  std::vector<FovCase> out;
  for (const double total : {10.0, 30.0, 90.0, 120.0, 150.0, 170.0}) {
    out.push_back({-total / 2, total / 2, total / 2, -total / 2});  // symmetric
    // Asymmetric: 30 % / 70 % split horizontally, 60 % / 40 % vertically (each side below 90 degrees).
    const double a = std::min(total * 0.7, 89.0), b = total - a;
    out.push_back({-b, a, std::min(total * 0.6, 89.0), -(total - std::min(total * 0.6, 89.0))});
  }
  out.push_back({10.0, 60.0, 40.0, 5.0});  // entirely off-axis (both tangents of an axis positive)
  return out;
}

TEST(StressProjection, ExtremeNearPlanesFieldsOfViewAndGuardBands) {
  const Extent display{64, 48};
  double worst_matrix_px = 0.0, worst_roundtrip_px = 0.0, worst_depth_rel = 0.0, worst_guard_px = 0.0;
  uint64_t checked = 0;
  const glm::dquat orientation =
      glm::normalize(glm::angleAxis(0.7, glm::normalize(glm::dvec3(0.2, 1.0, 0.1))));
  for (const glm::dvec3 position : {glm::dvec3(0.3, 1.6, -2.0), glm::dvec3(1e5, 3.7e4, -7.1e4)}) {
    for (const FovCase& f : fov_cases()) {
      View view;
      view.pose.position = position;
      view.pose.orientation = orientation;
      view.fov = Fov{float(f.left_deg * kDeg), float(f.right_deg * kDeg), float(f.up_deg * kDeg),
                     float(f.down_deg * kDeg)};
      ASSERT_FALSE(validate_fov(view.fov).has_value()) << f.left_deg << " " << f.right_deg;
      const Camera plain = Camera::with_guard_band(view, display, GuardBand{});
      for (const double guard_share : {0.0, 0.1, 0.25, 0.5}) {
        const GuardBand guard{uint32_t(std::lround(display.width * guard_share / 2)),
                              uint32_t(std::lround(display.height * guard_share / 2))};
        const Camera cam = Camera::with_guard_band(view, display, guard);
        ASSERT_FALSE(validate_camera(cam).has_value());
        for (const double near_plane : {1e-4, 1e-3, 1e-2, 0.1, 1.0}) {
          const glm::dmat4 vp = cam.view_projection(near_plane);
          ASSERT_TRUE(finite(cam.projection(near_plane)) && finite(vp));
          for (const double px : {0.0, 0.5, 17.25, double(cam.extent.width) - 0.5, double(cam.extent.width)}) {
            for (const double py : {0.0, 0.5, 11.75, double(cam.extent.height)}) {
              for (const double depth : {near_plane, near_plane * 1.5, 1.0, 1e3, 1e5}) {
                const glm::dvec3 p_eye = cam.eye_ray(px, py) * depth;
                const glm::dvec3 p = cam.T_world_eye.transform_point(p_eye);
                // Tolerances scale with the coordinates' rounding: |p| * 2^-52 over the depth.
                const double rel = std::max(1.0, glm::length(position) / depth);
                const Reprojection r = reproject(cam, p);
                ASSERT_NE(r.status, Reprojection::Status::kBehind);
                ASSERT_TRUE(std::isfinite(r.pixel.x) && std::isfinite(r.pixel.y) && std::isfinite(r.depth));
                const double roundtrip = std::max(std::fabs(r.pixel.x - px), std::fabs(r.pixel.y - py)) / rel;
                worst_roundtrip_px = std::max(worst_roundtrip_px, roundtrip);
                // The matrix path: clip -> NDC -> pixels, reversed-Z depth = near / depth.
                const glm::dvec4 clip = vp * glm::dvec4(p, 1.0);
                ASSERT_TRUE(std::isfinite(clip.x) && std::isfinite(clip.y) && std::isfinite(clip.z) &&
                            std::isfinite(clip.w) && clip.w > 0.0);
                const double mx = (clip.x / clip.w + 1.0) * 0.5 * cam.extent.width;
                const double my = (clip.y / clip.w + 1.0) * 0.5 * cam.extent.height;
                worst_matrix_px = std::max(worst_matrix_px, std::max(std::fabs(mx - px), std::fabs(my - py)) / rel);
                const double z = clip.z / clip.w;
                worst_depth_rel = std::max(worst_depth_rel, std::fabs(z - near_plane / depth) / (near_plane / depth) / rel);
                // The same point in the camera without guard band: shifted by the band on one side.
                const Reprojection q = reproject(plain, p);
                ASSERT_NE(q.status, Reprojection::Status::kBehind);
                worst_guard_px = std::max(worst_guard_px, std::max(std::fabs(q.pixel.x + guard.x - r.pixel.x),
                                                                   std::fabs(q.pixel.y + guard.y - r.pixel.y)) / rel);
                ++checked;
              }
            }
          }
        }
      }
    }
  }
  // Pixels per unit of max(1, |position| / depth): double rounding (2e-16), amplified by tangents up to 11
  // (170 degrees) and by pixel counts up to 96 per tangent unit; a single-precision step anywhere would
  // show as ~1e-6.
  constexpr double kPixelBound = 1e-10, kDepthBound = 1e-12;
  report("projection_extremes", "roundtrip_px_per_rel", worst_roundtrip_px, kPixelBound);
  report("projection_extremes", "matrix_px_per_rel", worst_matrix_px, kPixelBound);
  report("projection_extremes", "reversed_z_rel_error", worst_depth_rel, kDepthBound);
  report("projection_extremes", "guard_band_shift_px_per_rel", worst_guard_px, kPixelBound);
  std::printf("[stress] projection_extremes: %llu points checked\n", static_cast<unsigned long long>(checked));
  EXPECT_LE(worst_roundtrip_px, kPixelBound);
  EXPECT_LE(worst_matrix_px, kPixelBound);
  EXPECT_LE(worst_depth_rel, kDepthBound);
  EXPECT_LE(worst_guard_px, kPixelBound);
}

TEST(StressProjection, ReprojectionBehindAtAndOnTheEdgeOfTheOldEye) {
  for (const glm::dvec3 position : {glm::dvec3(0.0, 1.6, 0.0), glm::dvec3(1e5, -2e4, 6e4)}) {
    View view;
    view.pose.position = position;
    view.pose.orientation = glm::normalize(glm::dquat(0.9, 0.1, -0.3, 0.2));
    view.fov = Fov{-1.2f, 0.9f, 1.0f, -1.3f};
    const Camera cam = Camera::with_guard_band(view, Extent{64, 48}, GuardBand{8, 6});
    auto world = [&](const glm::dvec3& eye) { return cam.T_world_eye.transform_point(eye); };
    // At the eye, on the eye plane, and behind it: kBehind, nothing computed.
    for (const glm::dvec3 eye : {glm::dvec3(0.0), glm::dvec3(1.0, -2.0, 0.0), glm::dvec3(0.3, 0.2, 5.0),
                                 glm::dvec3(0.0, 0.0, 1e-300), glm::dvec3(1e3, 1e3, 1e-9)}) {
      const Reprojection r = reproject(cam, world(eye));
      EXPECT_EQ(r.status, Reprojection::Status::kBehind) << eye.x << "," << eye.y << "," << eye.z;
      EXPECT_TRUE(std::isfinite(r.depth));
    }
    // Non-finite input: kBehind, never a NaN pixel marked inside.
    for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
      const Reprojection r = reproject(cam, glm::dvec3(bad, 0.0, 0.0));
      EXPECT_NE(r.status, Reprojection::Status::kInside);
    }
    // On the edges of the image: [0, W) x [0, H) is inside; the status always agrees with the pixel, and the
    // pixel is within rounding of the edge.
    double worst_edge = 0.0;
    for (const double depth : {1e-3, 1.0, 1e4}) {
      for (const auto& [px, py] : {std::pair{0.0, 10.0}, std::pair{64.0 + 16.0, 10.0}, std::pair{20.0, 0.0},
                                   std::pair{20.0, 48.0 + 12.0}, std::pair{0.0, 0.0}}) {
        const Reprojection r = reproject(cam, world(cam.eye_ray(px, py) * depth));
        ASSERT_NE(r.status, Reprojection::Status::kBehind);
        const bool inside = r.pixel.x >= 0.0 && r.pixel.y >= 0.0 && r.pixel.x < cam.extent.width &&
                            r.pixel.y < cam.extent.height;
        EXPECT_EQ(r.status == Reprojection::Status::kInside, inside);
        worst_edge = std::max(worst_edge, std::max(std::fabs(r.pixel.x - px), std::fabs(r.pixel.y - py)));
      }
    }
    report(position.x > 1.0 ? "reprojection_edges_offset_1e5" : "reprojection_edges_origin", "edge_px_error",
           worst_edge, 1e-4);
    EXPECT_LE(worst_edge, 1e-4);
  }
}

}  // namespace
}  // namespace dhr::stress
