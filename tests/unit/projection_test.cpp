#include "math/projection.hpp"

#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/quaternion.hpp>

#include <cmath>

namespace dhr {
namespace {

View make_view(glm::dvec3 pos, glm::dquat q, Fov fov = Fov{-0.7f, 0.6f, 0.5f, -0.8f}) {
  View v;
  v.pose.position = pos;
  v.pose.orientation = q;
  v.fov = fov;
  return v;
}

TEST(Projection, GuardBandKeepsFocalLengthAndDisplayedRegion) {
  const View view = make_view({0, 0, 0}, glm::dquat(1, 0, 0, 0));
  const Extent display{1920, 1080};
  const Camera plain = Camera::with_guard_band(view, display, {});
  const Camera guarded = Camera::with_guard_band(view, display, GuardBand{32, 18});
  EXPECT_EQ(guarded.extent, (Extent{1984, 1116}));
  EXPECT_NEAR(plain.focal_x(), guarded.focal_x(), 1e-9);
  EXPECT_NEAR(plain.focal_y(), guarded.focal_y(), 1e-9);
  // Display pixel (i, j) sees the same direction as guarded pixel (i + 32, j + 18).
  for (double i : {0.5, 100.5, 1919.5}) {
    for (double j : {0.5, 540.5, 1079.5}) {
      const glm::dvec3 a = plain.eye_ray(i, j), b = guarded.eye_ray(i + 32, j + 18);
      EXPECT_NEAR(a.x, b.x, 1e-12);
      EXPECT_NEAR(a.y, b.y, 1e-12);
    }
  }
}

TEST(Projection, ScaleGuardBandRoundsPerSide) {
  EXPECT_EQ(scale_guard_band({32, 18}, {1920, 1080}, {320, 240}), (GuardBand{5, 4}));
  EXPECT_EQ(paper_guard_band({320, 240}), (GuardBand{5, 4}));
  EXPECT_EQ(paper_guard_band({1920, 1080}), (GuardBand{32, 18}));
  EXPECT_EQ(guard_band_from_total(64, 36), (GuardBand{32, 18}));
  EXPECT_EQ(guard_band_from_total(65, 36), std::nullopt);
  EXPECT_EQ(scale_guard_band({0, 0}, {1920, 1080}, {640, 480}), (GuardBand{0, 0}));
}

TEST(Projection, PixelRayReprojectsToSamePixel) {
  const glm::dquat q = glm::angleAxis(0.3, glm::normalize(glm::dvec3(0.2, 1.0, -0.1)));
  const Camera cam = Camera::with_guard_band(make_view({1.0, 1.6, -2.0}, q), {160, 120}, {4, 3});
  for (double px : {0.5, 17.25, 83.5, 167.5}) {
    for (double py : {0.5, 60.0, 125.5}) {
      const glm::dvec3 p = cam.T_world_eye.position + 3.7 * cam.world_ray(px, py);
      const Reprojection r = reproject(cam, p);
      ASSERT_EQ(r.status, Reprojection::Status::kInside);
      EXPECT_NEAR(r.pixel.x, px, 1e-9);
      EXPECT_NEAR(r.pixel.y, py, 1e-9);
    }
  }
}

TEST(Projection, MatrixAgreesWithReprojection) {
  const glm::dquat q = glm::angleAxis(-0.4, glm::dvec3(0, 1, 0));
  const Camera cam = Camera::with_guard_band(make_view({0.5, 1.2, 0.3}, q), {200, 100}, {5, 3});
  const double near_plane = 0.05;
  const glm::dmat4 vp = cam.view_projection(near_plane);
  const glm::dvec3 p = cam.T_world_eye.position + 2.0 * cam.world_ray(40.5, 77.25);
  const glm::dvec4 clip = vp * glm::dvec4(p, 1.0);
  const glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
  const Reprojection r = reproject(cam, p);
  EXPECT_NEAR((ndc.x + 1.0) * 0.5 * cam.extent.width, r.pixel.x, 1e-9);
  EXPECT_NEAR((ndc.y + 1.0) * 0.5 * cam.extent.height, r.pixel.y, 1e-9);
  EXPECT_NEAR(ndc.z, near_plane / r.depth, 1e-12);  // reversed-Z: nearer is larger
  EXPECT_GT(ndc.z, 0.0);
  EXPECT_LT(ndc.z, 1.0);
}

TEST(Projection, PointsBehindOrAtTheEyeAreRejected) {
  const Camera cam = Camera::with_guard_band(make_view({0, 0, 0}, glm::dquat(1, 0, 0, 0)), {64, 64}, {});
  EXPECT_EQ(reproject(cam, {0, 0, 1}).status, Reprojection::Status::kBehind);
  EXPECT_EQ(reproject(cam, {0, 0, 0}).status, Reprojection::Status::kBehind);
  EXPECT_EQ(reproject(cam, {5, 0, 0}).status, Reprojection::Status::kBehind);  // in the eye plane
  EXPECT_EQ(reproject(cam, {50, 0, -1}).status, Reprojection::Status::kOutside);
  EXPECT_EQ(reproject(cam, {0, 0, -1}).status, Reprojection::Status::kInside);
}

TEST(Projection, LargeWorldOffsetsKeepPrecision) {
  // The same relative geometry 1e5 m from the origin reprojects like at the origin.
  const glm::dquat q = glm::angleAxis(0.2, glm::dvec3(1, 0, 0));
  for (double offset : {0.0, 1e3, 1e5}) {
    const glm::dvec3 o(offset, 0.0, -offset);
    const Camera cam = Camera::with_guard_band(make_view(o + glm::dvec3(0, 1.6, 0), q), {320, 240}, {});
    const Reprojection r = reproject(cam, o + glm::dvec3(0.3, 1.1, -2.0));
    ASSERT_EQ(r.status, Reprojection::Status::kInside);
    const Camera ref = Camera::with_guard_band(make_view(glm::dvec3(0, 1.6, 0), q), {320, 240}, {});
    const Reprojection rr = reproject(ref, glm::dvec3(0.3, 1.1, -2.0));
    EXPECT_NEAR(r.pixel.x, rr.pixel.x, 1e-6);
    EXPECT_NEAR(r.pixel.y, rr.pixel.y, 1e-6);
  }
}

TEST(Projection, ValidateCamera) {
  Camera cam = Camera::with_guard_band(make_view({0, 0, 0}, glm::dquat(1, 0, 0, 0)), {64, 64}, {});
  EXPECT_FALSE(validate_camera(cam).has_value());
  Camera zero = cam;
  zero.extent = {0, 10};
  EXPECT_TRUE(validate_camera(zero).has_value());
  Camera huge = cam;
  huge.extent = {100000, 10};
  EXPECT_TRUE(validate_camera(huge).has_value());
  Camera nan = cam;
  nan.T_world_eye.position.x = std::nan("");
  EXPECT_TRUE(validate_camera(nan).has_value());
}

TEST(Pose, ComposeInverseAndValidate) {
  Pose a;
  a.position = {1, 2, 3};
  a.orientation = glm::angleAxis(0.7, glm::normalize(glm::dvec3(1, 1, 0)));
  const Pose id = a * a.inverse();
  EXPECT_NEAR(glm::length(id.position), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(id.orientation.w), 1.0, 1e-12);
  EXPECT_FALSE(validate_pose(a).has_value());
  Pose bad = a;
  bad.orientation = glm::dquat(0, 0, 0, 0);
  EXPECT_TRUE(validate_pose(bad).has_value());
  bad = a;
  bad.orientation = glm::dquat(1e308, 0, 0, 0);  // finite, but its norm overflows
  EXPECT_TRUE(validate_pose(bad).has_value());
  bad = a;
  bad.position.y = INFINITY;
  EXPECT_TRUE(validate_pose(bad).has_value());
  bad = a;
  bad.position.x = 2e6;
  EXPECT_TRUE(validate_pose(bad).has_value());
  Fov f;
  EXPECT_FALSE(validate_fov(f).has_value());
  f.angle_left = 0.9f;  // left > right
  EXPECT_TRUE(validate_fov(f).has_value());
}

}  // namespace
}  // namespace dhr
