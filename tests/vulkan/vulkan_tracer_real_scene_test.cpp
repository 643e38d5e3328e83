// The Vulkan tracer against the Embree reference on real scenes (issue 3's agreement criterion): the
// default room and every scene in ../shared/data/scenes, from their camera bookmarks or, for scenes without
// any, one camera in front of the bounding box.
#include "vulkan_tracer_agreement.hpp"

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "test_scenes.hpp"

namespace dhr::server::tracer_test {
namespace {

TEST_F(VulkanTracerTest, AgreesWithEmbreeOnTheDefaultRoom) {
  const std::string path = test::source_path(kDefaultScenePath);
  const Scene scene = load_scene_or_fail(path);
  const auto cameras = bookmark_cameras(path, {160, 120});
  ASSERT_FALSE(cameras.empty());
  expect_agreement(scene, cameras, vk_options(), embree_options());
}

TEST_F(VulkanTracerTest, AgreesWithEmbreeOnTheLivingRoom) {
  const std::string path = test::shared_data_path("scenes/living_room.glb");
  if (path.empty()) GTEST_SKIP() << "../shared/data not present: living_room.glb comparison skipped";
  const Scene scene = load_scene_or_fail(path);
  const auto cameras = bookmark_cameras(path, {96, 72});
  ASSERT_EQ(cameras.size(), 5u);
  expect_agreement(scene, cameras, vk_options(), embree_options());
}

// Every other scene in ../shared/data/scenes: its bookmarks (living_room_dense) or, for the glTF samples
// without any, one camera in front of the bounding box (as trace_bench). Small images: lavapipe is slow,
// and the 1M-triangle scenes cost mostly their BLAS builds.
TEST_F(VulkanTracerTest, AgreesWithEmbreeOnEveryOtherRealScene) {
  const std::string dir = test::shared_data_path("scenes");
  if (dir.empty()) GTEST_SKIP() << "../shared/data not present: real-scene comparisons skipped";
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
    const std::string ext = entry.path().extension().string();
    if ((ext == ".gltf" || ext == ".glb") && entry.path().filename() != "living_room.glb") {
      paths.push_back(entry.path().string());
    }
  }
  std::sort(paths.begin(), paths.end());
  // A partial copy of the data (scripts/gpu-run's bundle: the living room and its area- and sun-lit variants) has no
  // MANIFEST.md.
  if (test::shared_data_path("MANIFEST.md").empty()) {
    if (paths.empty()) GTEST_SKIP() << "a partial copy of ../shared/data: no other scene";
  } else {
    ASSERT_GE(paths.size(), 8u) << "the MANIFEST lists 9 scenes";
  }
  const Extent eye{64, 48};
  const GuardBand guard = paper_guard_band(eye);
  for (const std::string& path : paths) {
    SCOPED_TRACE(path);
    const Scene scene = load_scene_or_fail(path);
    std::vector<Camera> cameras;
    if (std::filesystem::exists(camera_bookmarks_path(path))) {
      cameras = bookmark_cameras(path, eye);
    } else {
      const View view{left_eye_pose(look_at_pose(front_bookmark(scene.bounds)).value()), symmetric_fov(90.0, eye)};
      cameras.push_back(Camera::with_guard_band(view, eye, guard));
    }
    ASSERT_FALSE(cameras.empty());
    expect_agreement(scene, cameras, vk_options(), embree_options());
  }
}

}  // namespace
}  // namespace dhr::server::tracer_test
