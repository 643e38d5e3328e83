// The dhr-server executable: --check exit codes and JSON, --snapshot files, argument errors.
#include "scene/camera_bookmarks.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dhr::server {
namespace {

struct RunResult {
  int exit_code = -1;
  std::string out;  // stdout; stderr goes to a file read into err
  std::string err;
};

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

RunResult run_server(const std::string& args) {
  const auto err_path = std::filesystem::temp_directory_path() / ("dhr_server_cli_err_" + std::to_string(::getpid()));
  const std::string command = quote(DHR_SERVER_EXE) + " " + args + " 2>" + quote(err_path.string());
  RunResult r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_path);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  std::filesystem::remove(err_path);
  return r;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

TEST(ServerCli, HelpExitsZero) {
  const RunResult r = run_server("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--snapshot"), std::string::npos);
}

TEST(ServerCli, CheckOnTheDefaultScenePrintsOneJsonLine) {
  const RunResult r = run_server("--check");  // the default scene
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto out = lines(r.out);
  ASSERT_EQ(out.size(), 1u) << r.out;
  const auto j = nlohmann::json::parse(out[0]);
  EXPECT_NE(j.at("scene").get<std::string>().find("default_room.gltf"), std::string::npos);
  EXPECT_GT(j.at("meshes").get<int>(), 0);
  EXPECT_GT(j.at("triangles").get<int>(), 0);
  EXPECT_GT(j.at("lights").get<int>(), 0);
  EXPECT_GT(j.at("materials").get<int>(), 0);
  EXPECT_GE(j.at("images").get<int>(), 0);
  EXPECT_TRUE(j.at("warnings").is_array());
}

TEST(ServerCli, CheckOnTheLivingRoom) {
  const std::string path = test::shared_data_path("scenes/living_room.glb");
  if (path.empty()) GTEST_SKIP() << "../shared/data not present";
  const RunResult r = run_server("--check --scene " + quote(path));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(lines(r.out).at(0));
  EXPECT_EQ(j.at("triangles").get<int>(), 163448);
  EXPECT_EQ(j.at("lights").get<int>(), 3);
}

// The moving living room: both backends play its animations (no warning).
TEST(ServerCli, CheckOnTheMovingLivingRoomWarnsForNoBackend) {
  const std::string path = test::shared_data_path("scenes/living_room_moving.glb");
  if (path.empty()) GTEST_SKIP() << "../shared/data not present";
  const RunResult r = run_server("--check --scene " + quote(path));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto warnings = nlohmann::json::parse(lines(r.out).at(0)).at("warnings");
  for (const auto& w : warnings) EXPECT_EQ(w.get<std::string>().find("animation"), std::string::npos) << w;
  const RunResult vk = run_server("--check --backend vulkan --scene " + quote(path));
  ASSERT_EQ(vk.exit_code, 0) << vk.err;
  for (const auto& w : nlohmann::json::parse(lines(vk.out).at(0)).at("warnings"))
    EXPECT_EQ(w.get<std::string>().find("animation"), std::string::npos) << w;
}

// Each light's type and extent: the area sibling of the default room, and --lights with a sun disk.
TEST(ServerCli, CheckListsEachLightsTypeAndExtent) {
  const RunResult r = run_server("--check --scene " + quote(test::source_path("assets/scenes/default_room_area.gltf")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(lines(r.out).at(0));
  const auto& details = j.at("light_details");
  ASSERT_EQ(details.size(), 3u) << r.out;
  EXPECT_EQ(details[0].at("name"), "ceiling_panel");
  EXPECT_EQ(details[0].at("type"), "rect");
  EXPECT_EQ(details[0].at("extent"), "rect 0.8 x 0.4 m");
  EXPECT_EQ(details[0].at("spec").get<std::string>().rfind("rect:0.5,2.70000005,0.300000012:0,-1,", 0), 0u) << details[0];
  EXPECT_EQ(details[1].at("extent"), "point");
  EXPECT_EQ(details[2].at("extent"), "point, sphere r 0.05 m");
  EXPECT_TRUE(j.at("warnings").empty()) << j.at("warnings");
  const RunResult sun = run_server("--check --lights 'dir:0,-1,0:1,1,1:3:angle_deg=0.53'");
  ASSERT_EQ(sun.exit_code, 0) << sun.err;
  const auto s = nlohmann::json::parse(lines(sun.out).at(0));
  EXPECT_EQ(s.at("light_details").at(0).at("extent"), "dir, sun disk 0.53 deg");
  EXPECT_EQ(s.at("light_details").at(0).at("spec"), "dir:0,-1,0:1,1,1:3:angle_deg=0.529999971");
}

// The mask layout a soft-capable client gets (docs/protocol.md, "Mask layout"), and soft lights demoted to one bit
// when 32 bits do not hold every level field.
TEST(ServerCli, CheckSaysTheMaskLayout) {
  const RunResult r = run_server("--check --scene " + quote(test::source_path("assets/scenes/default_room_area.gltf")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto layout = nlohmann::json::parse(lines(r.out).at(0)).at("mask_layout");
  EXPECT_EQ(layout.at("bits"), 7);
  EXPECT_EQ(layout.at("mask_bits"), 8);
  ASSERT_EQ(layout.at("soft_lights").size(), 2u) << layout;
  EXPECT_EQ(layout.at("soft_lights")[0].at("name"), "ceiling_panel");
  EXPECT_EQ(layout.at("soft_lights")[0].at("first_bit"), 0);
  EXPECT_EQ(layout.at("soft_lights")[0].at("bits"), 3);
  EXPECT_EQ(layout.at("soft_lights")[1].at("first_bit"), 4);
  EXPECT_TRUE(layout.at("demoted").empty());
  std::string suns;
  for (int i = 0; i < 11; ++i) suns += std::string(i ? ";" : "") + "dir:0,-1,0:1,1,1:3:angle_deg=0.53";
  const RunResult many = run_server("--check --lights '" + suns + "'");
  ASSERT_EQ(many.exit_code, 0) << many.err;
  const auto m = nlohmann::json::parse(lines(many.out).at(0)).at("mask_layout");
  EXPECT_EQ(m.at("bits"), 31);  // ten level fields and the eleventh light's bit
  EXPECT_EQ(m.at("soft_lights").size(), 10u);
  EXPECT_EQ(m.at("demoted").size(), 1u);
}

TEST(ServerCli, CheckRejectsUnusableScenesWithOneLine) {
  std::vector<std::string> bad = {"/nonexistent/missing.gltf"};
  if (const std::string draco = test::shared_data_path("gltf-bad/draco/2CylinderEngine.gltf"); !draco.empty())
    bad.push_back(draco);
  for (const std::string& path : bad) {
    const RunResult r = run_server("--check --scene " + quote(path));
    EXPECT_EQ(r.exit_code, 2) << path;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_EQ(lines(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(path), std::string::npos) << r.err;
  }
}

TEST(ServerCli, BadArgumentsExitTwo) {
  for (const char* args : {"--bogus", "--check --snapshot /tmp/x", "--check --backend optix", "--check --eye-size 0x480",
                           "--check --eye-size 640", "--check --guard -2x4", "--check --fov-deg 0",
                           "--check --lights point:1,2", "--snapshot /tmp/dhr_x --camera 1,2,3",
                           "--check --threads abc", ""}) {
    const RunResult r = run_server(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_FALSE(r.err.empty()) << args;
  }
}

TEST(ServerCli, SnapshotWritesPngsPerBookmarkAndLight) {
  const auto dir = std::filesystem::temp_directory_path() / ("dhr_snapshot_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const RunResult r = run_server("--snapshot " + quote(dir.string()) + " --backend embree --eye-size 64x48");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string error;
  const auto bookmarks =
      load_camera_bookmarks(camera_bookmarks_path(test::source_path(kDefaultScenePath)), &error).value();
  const auto out = lines(r.out);
  ASSERT_EQ(out.size(), bookmarks.size()) << r.out;
  for (size_t i = 0; i < bookmarks.size(); ++i) {
    const auto j = nlohmann::json::parse(out[i]);
    EXPECT_EQ(j.at("bookmark"), bookmarks[i].name);
    EXPECT_EQ(j.at("backend"), "embree");
    EXPECT_EQ(j.at("extent")[0].get<int>(), 64 + 2);  // 64x36 at 1920x1080 -> 2x2 at 64x48
    EXPECT_EQ(j.at("stats").at("pixels").get<int>(), 66 * 50);
    const int lights = j.at("lights").get<int>();
    ASSERT_GT(lights, 0);
    EXPECT_EQ(j.at("files").size(), static_cast<size_t>(lights) + 1);
    for (int li = 0; li < lights; ++li)
      EXPECT_TRUE(std::filesystem::exists(dir / (bookmarks[i].name + "_light" + std::to_string(li) + ".png")));
    const auto shaded = dir / (bookmarks[i].name + "_shaded.png");
    ASSERT_TRUE(std::filesystem::exists(shaded));
    EXPECT_GT(std::filesystem::file_size(shaded), 100u);
  }
  std::filesystem::remove_all(dir);
}

TEST(ServerCli, SnapshotWithExplicitCamerasAndLights) {
  const auto dir = std::filesystem::temp_directory_path() / ("dhr_snapshot_cam_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const RunResult r = run_server("--snapshot " + quote(dir.string()) +
                                 " --backend embree --eye-size 40x30 --guard 0x0 --camera 0,1.6,1:0,0.5,-1"
                                 " --camera 1,1.6,0:0,0.5,0 --lights 'point:0,2,0:1,1,1:10;dir:0,-1,0.2:1,1,1:2'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(lines(r.out).size(), 2u);
  for (const char* name : {"camera0_light0.png", "camera0_light1.png", "camera0_shaded.png", "camera1_shaded.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  EXPECT_FALSE(std::filesystem::exists(dir / "camera0_light2.png"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dhr::server
