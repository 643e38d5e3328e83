// load_session_scene (scene/session_scene.hpp): the scene both ends of a session load, `--lights` applied; an animated
// scene loads without a warning (both ends play it on the scene clock).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "scene/session_scene.hpp"

namespace dhr {
namespace {

namespace fs = std::filesystem;

bool has_warning_with(const Scene& scene, const std::string& words) {
  return std::any_of(scene.warnings.begin(), scene.warnings.end(),
                     [&](const std::string& w) { return w.find(words) != std::string::npos; });
}

TEST(SessionScene, StaticSceneLoadsWithoutAnAnimationWarning) {
  std::string error;
  const auto scene = load_session_scene((fs::path(DHR_SOURCE_DIR) / kDefaultScenePath).string(), "", &error);
  ASSERT_TRUE(scene.has_value()) << error;
  EXPECT_TRUE(scene->animation.empty());
  EXPECT_FALSE(has_warning_with(*scene, "animation"));
}

TEST(SessionScene, LightsSpecReplacesTheLightsAndBadSpecsAreRefused) {
  const std::string path = (fs::path(DHR_SOURCE_DIR) / kDefaultScenePath).string();
  std::string error;
  const auto scene = load_session_scene(path, "point:0,2,0:1,1,1:10", &error);
  ASSERT_TRUE(scene.has_value()) << error;
  ASSERT_EQ(scene->lights.size(), 1u);
  EXPECT_FALSE(load_session_scene(path, "point:0,2,0:1,1,1:nan", &error).has_value());
  EXPECT_NE(error.find("--lights"), std::string::npos) << error;
}

TEST(SessionScene, MissingFileIsAnError) {
  std::string error;
  EXPECT_FALSE(load_session_scene("/nonexistent/scene.glb", "", &error).has_value());
  EXPECT_FALSE(error.empty());
}

TEST(SessionScene, AnAnimatedSceneLoadsWithoutAWarning) {
  const fs::path path = fs::path(DHR_SHARED_DATA_DIR) / "scenes/living_room_moving.glb";
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent (../shared/data)";
  std::string error;
  const auto client = load_session_scene(path.string(), "", &error);
  ASSERT_TRUE(client.has_value()) << error;
  EXPECT_FALSE(client->animation.empty());
  EXPECT_EQ(describe_animations(*client), "1 animation(s), 3 track(s)");
  EXPECT_FALSE(has_warning_with(*client, "animation"));  // both ends play them on the scene clock
}

}  // namespace
}  // namespace dhr
