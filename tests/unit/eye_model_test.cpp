// Eye model (head pose -> eye views) and trace placement in a scene.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <unistd.h>

#include "traces/eye_model.hpp"
#include "math/projection.hpp"

namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

glm::dquat yaw(double radians) { return glm::angleAxis(radians, glm::dvec3(0.0, 1.0, 0.0)); }

TEST(EyeModel, EyesAreIpdApartAlongHeadX) {
  dhr::Pose head;
  head.position = {1.0, 1.6, -2.0};
  head.orientation = glm::normalize(glm::dquat(0.9, 0.1, -0.3, 0.2));
  const dhr::EyeModel model;
  EXPECT_EQ(model.ipd_metres, 0.063);
  const auto views = model.views(head);
  const glm::dvec3 head_x = head.orientation * glm::dvec3(1.0, 0.0, 0.0);
  const glm::dvec3 between = views[1].pose.position - views[0].pose.position;
  EXPECT_NEAR(glm::length(between), 0.063, 1e-12);
  EXPECT_NEAR(glm::dot(between, head_x), 0.063, 1e-12);  // right eye on the head's +X side
  EXPECT_NEAR(glm::length(0.5 * (views[0].pose.position + views[1].pose.position) - head.position), 0.0, 1e-12);
  for (const dhr::View& v : views) {
    EXPECT_NEAR(glm::dot(v.pose.orientation, head.orientation), 1.0, 1e-12);
    EXPECT_FALSE(dhr::validate_fov(v.fov).has_value());
    EXPECT_FALSE(dhr::validate_pose(v.pose).has_value());
  }

  dhr::EyeModel raised;
  raised.ipd_metres = 0.07;
  raised.eye_height_offset_metres = 0.1;
  const auto raised_views = raised.views(dhr::Pose{});
  EXPECT_NEAR(raised_views[0].pose.position.x, -0.035, 1e-15);
  EXPECT_NEAR(raised_views[1].pose.position.x, 0.035, 1e-15);
  EXPECT_NEAR(raised_views[1].pose.position.y, 0.1, 1e-15);
}

TEST(EyeModel, DefaultFovsAreValidAndMirrored) {
  const dhr::Fov left = dhr::typical_headset_fov(0);
  const dhr::Fov right = dhr::typical_headset_fov(1);
  EXPECT_FALSE(dhr::validate_fov(left).has_value());
  EXPECT_FALSE(dhr::validate_fov(right).has_value());
  EXPECT_LT(left.angle_left, -right.angle_right + 1e-6f);  // wider towards each temple
  EXPECT_EQ(left.angle_left, -right.angle_right);
  EXPECT_EQ(left.angle_right, -right.angle_left);
  EXPECT_LT(left.angle_left, -left.angle_right);  // the temple side is the wider one
  // Square pixels at 1832x1920.
  const dhr::Tangents t = dhr::Tangents::from_fov(left);
  EXPECT_NEAR(t.width() / t.height(), 1832.0 / 1920.0, 0.005);

  const dhr::Fov monado = dhr::monado_simulated_fov();
  EXPECT_FALSE(dhr::validate_fov(monado).has_value());
  EXPECT_NEAR(monado.angle_right, 0.742, 0.001);  // PLATFORM.md: about +-0.742 horizontal
  EXPECT_NEAR(monado.angle_up, 0.779, 0.001);     // and +-0.779 vertical
  EXPECT_EQ(dhr::EyeModel::monado_simulated().fov[1].angle_up, monado.angle_up);
}

TEST(Placement, YawOfPoses) {
  EXPECT_NEAR(dhr::yaw_of(glm::dquat(1.0, 0.0, 0.0, 0.0)), 0.0, 1e-15);
  EXPECT_NEAR(dhr::yaw_of(yaw(0.7)), 0.7, 1e-12);
  EXPECT_NEAR(dhr::yaw_of(yaw(-2.5)), -2.5, 1e-12);
  // Pitch and roll do not change the heading.
  const glm::dquat tilted = yaw(1.2) * glm::angleAxis(0.4, glm::dvec3(1, 0, 0)) * glm::angleAxis(0.3, glm::dvec3(0, 0, 1));
  EXPECT_NEAR(dhr::yaw_of(tilted), 1.2, 0.2);  // roll shifts it a little; pitch alone does not
  EXPECT_NEAR(dhr::yaw_of(yaw(1.2) * glm::angleAxis(0.4, glm::dvec3(1, 0, 0))), 1.2, 1e-12);
  // Straight down and straight up: the heading is where the top of the head points.
  EXPECT_NEAR(dhr::yaw_of(yaw(0.5) * glm::angleAxis(-kPi / 2.0, glm::dvec3(1, 0, 0))), 0.5, 1e-9);
  EXPECT_NEAR(dhr::yaw_of(yaw(0.5) * glm::angleAxis(kPi / 2.0, glm::dvec3(1, 0, 0))), 0.5, 1e-9);
}

TEST(Placement, RecentreStartsTheTraceAtThePlacement) {
  dhr::Pose first;
  first.position = {0.3, 0.07, 0.2};
  first.orientation = yaw(0.8) * glm::angleAxis(0.2, glm::dvec3(1, 0, 0));
  dhr::TracePlacement placement;
  placement.translation = {2.55, 1.6, 1.7};
  placement.yaw_radians = -1.0;
  const dhr::Pose T_scene_trace = dhr::placement_transform(placement, first);
  const dhr::Pose placed = T_scene_trace * first;
  EXPECT_NEAR(glm::length(placed.position - placement.translation), 0.0, 1e-12);
  EXPECT_NEAR(dhr::yaw_of(placed.orientation), -1.0, 1e-12);
  // Pitch is kept: the forward axis still points 0.2 rad up (a positive rotation about +X lifts -Z).
  const glm::dvec3 forward = placed.orientation * glm::dvec3(0, 0, -1);
  EXPECT_NEAR(std::asin(forward.y), 0.2, 1e-12);
  // Motion relative to the first pose keeps its length.
  dhr::Pose later = first;
  later.position += glm::dvec3(0.0, 0.0, -1.0);
  EXPECT_NEAR(glm::length((T_scene_trace * later).position - placed.position), 1.0, 1e-12);

  placement.recentre = false;
  const dhr::Pose raw = dhr::placement_transform(placement, first);
  EXPECT_NEAR(glm::length((raw * dhr::Pose{}).position - placement.translation), 0.0, 1e-12);
}

TEST(Placement, FromCameraFile) {
  const fs::path dir = fs::temp_directory_path() / ("dhr_eye_model_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "room.cameras.json")
      << R"({"cameras": [{"name": "a", "position": [1, 1.6, 2], "target": [1, 0.5, 0]}, )"
      << R"({"name": "b", "position": [0, 0, 0], "target": [1, 0, 0]}]})";
  std::string note;
  const dhr::TracePlacement p = dhr::default_trace_placement((dir / "room.glb").string(), &note);
  EXPECT_EQ(p.translation, glm::dvec3(1.0, 1.6, 2.0));
  EXPECT_NEAR(p.yaw_radians, 0.0, 1e-15);  // looking towards -Z
  EXPECT_TRUE(p.recentre);
  EXPECT_NE(note.find("first camera"), std::string::npos) << note;

  std::ofstream(dir / "bad.cameras.json") << R"({"cameras": [{"position": [1, "x", 2], "target": [0, 0, 0]}]})";
  const dhr::TracePlacement fallback = dhr::default_trace_placement((dir / "bad.gltf").string(), &note);
  EXPECT_EQ(fallback.translation, glm::dvec3(0.0, 1.6, 0.0));
  EXPECT_NE(note.find("bad.cameras.json"), std::string::npos) << note;

  const dhr::TracePlacement none = dhr::default_trace_placement((dir / "none.glb").string(), &note);
  EXPECT_EQ(none.translation, glm::dvec3(0.0, 1.6, 0.0));
  EXPECT_NE(note.find("no "), std::string::npos) << note;
  fs::remove_all(dir);

  // Facing +X from the camera: a quarter turn to the right, i.e. yaw -pi/2.
  EXPECT_NEAR(dhr::placement_from_camera({0, 0, 0}, {1, 0, 0}).yaw_radians, -kPi / 2.0, 1e-15);
}

TEST(Placement, SceneCameraFilesOfTheRepository) {
  const fs::path scene = fs::path(DHR_SOURCE_DIR) / "assets/scenes/default_room.gltf";
  if (!fs::exists(scene)) GTEST_SKIP() << "no " << scene;
  std::string note;
  const dhr::TracePlacement p = dhr::default_trace_placement(scene.string(), &note);
  EXPECT_NE(note.find("first camera"), std::string::npos) << note;
  EXPECT_NEAR(p.translation.y, 1.6, 1e-12);
}

TEST(TraceViews, RecordedEyesWinOverTheModel) {
  dhr::PoseTrace trace;
  dhr::TraceSample s;
  s.head.position = {0.0, 0.0, 0.0};
  s.eye[0].position = {-0.04, 0.0, 0.0};
  s.eye[1].position = {0.04, 0.0, 0.0};
  s.fov[0] = dhr::monado_simulated_fov();
  s.fov[1] = dhr::monado_simulated_fov();
  trace.samples = {s};
  dhr::Pose T_scene_trace;
  T_scene_trace.position = {0.0, 1.6, 0.0};
  const dhr::EyeModel model;
  auto views = dhr::trace_views(trace, s, model, T_scene_trace);
  EXPECT_NEAR(views[1].pose.position.x, 0.0315, 1e-15);  // the model
  EXPECT_EQ(views[1].fov.angle_right, model.fov[1].angle_right);
  trace.has_eye_poses = true;
  trace.has_fov = true;
  views = dhr::trace_views(trace, s, model, T_scene_trace);
  EXPECT_NEAR(views[1].pose.position.x, 0.04, 1e-15);  // the recording
  EXPECT_NEAR(views[1].pose.position.y, 1.6, 1e-15);
  EXPECT_EQ(views[1].fov.angle_right, s.fov[1].angle_right);
}

}  // namespace
