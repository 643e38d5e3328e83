// Camera bookmark files, --camera specs, look-at poses, eye offsets.
#include "scene/camera_bookmarks.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace dhr::server {
namespace {

std::string write_temp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("dhr_bookmarks_" + std::to_string(::getpid()) + name);
  std::ofstream(path) << text;
  return path.string();
}

TEST(CameraBookmarks, PathBesideTheScene) {
  EXPECT_EQ(camera_bookmarks_path("/a/b/living_room.glb"), "/a/b/living_room.cameras.json");
  EXPECT_EQ(camera_bookmarks_path("x.gltf"), "x.cameras.json");
}

TEST(CameraBookmarks, LoadsTheDefaultScenesFile) {
  std::string error;
  auto b = load_camera_bookmarks(camera_bookmarks_path(test::source_path(kDefaultScenePath)), &error);
  ASSERT_TRUE(b) << error;
  ASSERT_FALSE(b->empty());
  EXPECT_FALSE(b->front().name.empty());
}

TEST(CameraBookmarks, LoadsTheLivingRoomFile) {
  const std::string path = test::shared_data_path("scenes/living_room.cameras.json");
  if (path.empty()) GTEST_SKIP() << "../shared/data not present";
  std::string error;
  auto b = load_camera_bookmarks(path, &error);
  ASSERT_TRUE(b) << error;
  ASSERT_EQ(b->size(), 5u);
  EXPECT_EQ(b->at(0).name, "doorway_overview");
  EXPECT_EQ(b->at(0).position, glm::dvec3(2.55, 1.6, 1.7));
  EXPECT_EQ(b->at(0).target, glm::dvec3(-0.8, 0.55, -1.3));
}

TEST(CameraBookmarks, RejectsBadFiles) {
  std::string error;
  EXPECT_FALSE(load_camera_bookmarks("/nonexistent/x.cameras.json", &error));
  EXPECT_NE(error.find("/nonexistent/x.cameras.json"), std::string::npos);
  const char* bad[] = {
      "not json",
      "[]",
      R"({"cameras": 3})",
      R"({"cameras": []})",
      R"({"cameras": [{"position": [0,1,0]}]})",
      R"({"cameras": [{"position": [0,1,0], "target": [0,1,"x"]}]})",
      R"({"cameras": [{"position": [0,1,0], "target": [0,1,0]}]})",
      R"({"cameras": [{"position": [0,1,0], "target": [0,5,0]}]})",
      R"({"cameras": [{"name": 5, "position": [0,1,0], "target": [1,1,0]}]})",
      R"({"up": [0,0,0], "cameras": [{"position": [0,1,0], "target": [1,1,0]}]})",
  };
  for (const char* text : bad) {
    const std::string path = write_temp("bad.json", text);
    EXPECT_FALSE(load_camera_bookmarks(path, &error)) << text;
    EXPECT_EQ(error.rfind(path, 0), 0u) << error;
    std::filesystem::remove(path);
  }
}

TEST(CameraBookmarks, ParsesCameraSpecs) {
  std::string error;
  auto b = parse_camera_spec("1,2.5,-3:0,1,0", &error);
  ASSERT_TRUE(b) << error;
  EXPECT_EQ(b->position, glm::dvec3(1.0, 2.5, -3.0));
  EXPECT_EQ(b->target, glm::dvec3(0.0, 1.0, 0.0));
  for (const char* bad : {"", "1,2,3", "1,2:3,4,5", "1,2,3:4,5,6,7", "a,b,c:1,2,3", "1,2,3:1,2,3", "0,0,0:0,5,0",
                          "1,2,nan:0,0,0", "1,2,3:0,0,1e300"}) {
    EXPECT_FALSE(parse_camera_spec(bad, &error)) << bad;
    EXPECT_FALSE(error.empty());
  }
}

TEST(CameraBookmarks, LookAtPointsMinusZAtTheTarget) {
  CameraBookmark b;
  b.position = {1.0, 2.0, 3.0};
  b.target = {4.0, 0.0, -1.0};
  const Pose pose = look_at_pose(b).value();
  const glm::dvec3 forward = pose.orientation * glm::dvec3(0, 0, -1);
  EXPECT_NEAR(glm::length(forward - glm::normalize(b.target - b.position)), 0.0, 1e-12);
  const glm::dvec3 right = pose.orientation * glm::dvec3(1, 0, 0);
  EXPECT_NEAR(right.y, 0.0, 1e-12);  // no roll
  EXPECT_GT((pose.orientation * glm::dvec3(0, 1, 0)).y, 0.0);
}

TEST(CameraBookmarks, LeftEyeIsHalfAnIpdToTheLeft) {
  CameraBookmark b;
  b.position = {0.0, 1.6, 0.0};
  b.target = {0.0, 1.6, -1.0};  // looking down -Z: right is +X
  const Pose eye = left_eye_pose(look_at_pose(b).value());
  EXPECT_NEAR(eye.position.x, -0.0315, 1e-12);
  EXPECT_NEAR(eye.position.y, 1.6, 1e-12);
  EXPECT_NEAR(eye.position.z, 0.0, 1e-12);
}

TEST(CameraBookmarks, SymmetricFovFollowsTheAspectRatio) {
  const Fov fov = symmetric_fov(90.0, Extent{640, 480});
  EXPECT_NEAR(std::tan(fov.angle_right), 1.0, 1e-6);
  EXPECT_NEAR(std::tan(fov.angle_up), 0.75, 1e-6);
  EXPECT_FLOAT_EQ(fov.angle_left, -fov.angle_right);
  EXPECT_FLOAT_EQ(fov.angle_down, -fov.angle_up);
}

}  // namespace
}  // namespace dhr::server
