// The session layer's pure parts, without a runtime: result and state names, format choice,
// Vulkan version checks, eye pose statistics and the smoke report's JSON.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <thread>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

#include "smoke_report.hpp"
#include "watchdog.hpp"
#include "xr/session.hpp"
#include "xr/swapchain.hpp"
#include "xr/vulkan_binding.hpp"
#include "xr/xr_check.hpp"

namespace dhr::xr {
namespace {

TEST(XrCheck, NamesResults) {
  EXPECT_EQ(result_name(XR_SUCCESS), "XR_SUCCESS");
  EXPECT_EQ(result_name(XR_ERROR_RUNTIME_UNAVAILABLE), "XR_ERROR_RUNTIME_UNAVAILABLE");
  EXPECT_EQ(result_name(XR_TIMEOUT_EXPIRED), "XR_TIMEOUT_EXPIRED");
  EXPECT_EQ(result_name(static_cast<XrResult>(-987654)), "XR_UNKNOWN_RESULT_-987654");
}

XrResult failing_call() { return XR_ERROR_SESSION_LOST; }

XrResult try_wrapper() {
  DHR_XR_TRY(failing_call());
  return XR_SUCCESS;
}

TEST(XrCheck, CheckThrowsWithNameExpressionAndLocation) {
  try {
    DHR_XR_CHECK(failing_call());
    FAIL() << "no throw";
  } catch (const XrError& e) {
    EXPECT_EQ(e.result(), XR_ERROR_SESSION_LOST);
    const std::string what = e.what();
    EXPECT_NE(what.find("XR_ERROR_SESSION_LOST"), std::string::npos) << what;
    EXPECT_NE(what.find("failing_call()"), std::string::npos) << what;
    EXPECT_NE(what.find("xr_parts_test.cpp:"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line";
  }
  EXPECT_NO_THROW(DHR_XR_CHECK(XR_SESSION_LOSS_PENDING));  // success codes pass
}

TEST(XrCheck, TryReturnsTheFailure) { EXPECT_EQ(try_wrapper(), XR_ERROR_SESSION_LOST); }

TEST(XrSession, StateNames) {
  EXPECT_EQ(session_state_name(XR_SESSION_STATE_FOCUSED), "FOCUSED");
  EXPECT_EQ(session_state_name(XR_SESSION_STATE_LOSS_PENDING), "LOSS_PENDING");
  EXPECT_EQ(session_state_name(static_cast<XrSessionState>(4242)), "STATE_4242");
}

TEST(XrSwapchain, PrefersRequestedEncodingThenFallsBack) {
  const std::vector<int64_t> runtime = {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_B8G8R8A8_UNORM,
                                        VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB,
                                        VK_FORMAT_R8G8B8A8_SRGB};
  EXPECT_EQ(choose_color_format(runtime, ColorEncoding::kSrgb), VK_FORMAT_R8G8B8A8_SRGB);
  EXPECT_EQ(choose_color_format(runtime, ColorEncoding::kUnorm), VK_FORMAT_R8G8B8A8_UNORM);
  const std::vector<int64_t> only_bgra_unorm = {VK_FORMAT_D32_SFLOAT, VK_FORMAT_B8G8R8A8_UNORM};
  EXPECT_EQ(choose_color_format(only_bgra_unorm, ColorEncoding::kSrgb), VK_FORMAT_B8G8R8A8_UNORM);
  const std::vector<int64_t> none = {VK_FORMAT_D32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT};
  EXPECT_EQ(choose_color_format(none, ColorEncoding::kSrgb), std::nullopt);
  EXPECT_EQ(choose_color_format({}, ColorEncoding::kUnorm), std::nullopt);
}

TEST(XrVulkanBinding, VersionCheckComparesMajorMinor) {
  const VulkanRequirements requirements{XR_MAKE_VERSION(1, 1, 0), XR_MAKE_VERSION(1, 3, 0)};
  EXPECT_FALSE(vulkan_version_supported(VK_API_VERSION_1_0, requirements));
  EXPECT_TRUE(vulkan_version_supported(VK_MAKE_API_VERSION(0, 1, 1, 0), requirements));
  EXPECT_TRUE(vulkan_version_supported(VK_API_VERSION_1_3, requirements));
  // Newer than the runtime tested is allowed (maxApiVersionSupported is not a hard limit).
  EXPECT_TRUE(vulkan_version_supported(VK_MAKE_API_VERSION(0, 1, 4, 0), requirements));
}

XrView view_at(float x, float y, float z) {
  XrView view{};
  view.type = XR_TYPE_VIEW;
  view.pose.orientation.w = 1.0f;
  view.pose.position = {x, y, z};
  return view;
}

TEST(SmokeReport, EyePoseStatsTrackRangeAndDistance) {
  EyePoseStats stats;
  EXPECT_EQ(stats.mean_eye_distance(), 0.0);
  stats.add({view_at(-0.03f, 1.6f, 0.0f), view_at(0.03f, 1.6f, 0.0f)});
  stats.add({view_at(-0.01f, 1.5f, 0.1f), view_at(0.05f, 1.5f, 0.1f)});
  EXPECT_EQ(stats.samples(), 2u);
  EXPECT_NEAR(stats.mean_eye_distance(), 0.06, 1e-6);
  EXPECT_NEAR(stats.min(0).x, -0.03, 1e-6);
  EXPECT_NEAR(stats.max(0).x, -0.01, 1e-6);
  EXPECT_NEAR(stats.min(1).y, 1.5, 1e-6);
  EXPECT_NEAR(stats.max(1).z, 0.1, 1e-6);
}

TEST(SmokeReport, JsonHasEveryFieldAndNullForMissingPoses) {
  SmokeReport report;
  report.runtime = "Test Runtime 1.2.3";
  report.system = "Test HMD";
  report.eye_size = {{{320, 240}, {320, 240}}};
  report.frames = 300;
  report.fps = 90.0;
  report.reached_focused = true;
  report.states = {"IDLE", "READY", "EXITING"};
  report.exit = "clean";
  nlohmann::json j = nlohmann::json::parse(smoke_report_json(report));
  for (const char* key : {"runtime", "system", "eye_size", "frames", "fps", "reached_focused",
                          "states", "pose_range", "ipd_m", "exit"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_TRUE(j["pose_range"][0].is_null());  // no valid pose seen: no made-up range
  EXPECT_EQ(j["eye_size"][1][0], 320);
  EXPECT_EQ(j["states"].back(), "EXITING");

  report.poses.add({view_at(0.0f, 0.0f, 0.0f),
                    view_at(std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f)});
  j = nlohmann::json::parse(smoke_report_json(report));
  EXPECT_TRUE(j["pose_range"][1]["min"][0].is_null()) << "NaN must not look like a number";
  EXPECT_EQ(smoke_report_json(report).find('\n'), std::string::npos) << "one line";
}

TEST(Watchdog, DisarmedInTimeDoesNothing) {
  { Watchdog watchdog(std::chrono::seconds(30), "not reached"); }
  SUCCEED();
}

TEST(WatchdogDeathTest, EndsAStuckProcessWithOneLine) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        Watchdog watchdog(std::chrono::milliseconds(50), "stuck in a runtime call");
        std::this_thread::sleep_for(std::chrono::seconds(30));
      },
      testing::ExitedWithCode(Watchdog::kExitCode), "error: stuck in a runtime call");
}

}  // namespace
}  // namespace dhr::xr
