// End-to-end: dhr-xrclient --smoke against Monado's simulated HMD (through
// runtime-config/with-monado), and the client's behaviour without a runtime.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "child_process.hpp"

namespace dhr::test {
namespace {

// The simulated HMD's IPD (Monado's default OXR_DEBUG_IPD_MM) and the tolerance we accept.
constexpr double kExpectedIpdM = 0.063;
constexpr double kIpdToleranceM = 0.002;
// Caps that turn a hang into a failure; generous, since ctest may run tests in parallel on 2 cores.
constexpr std::chrono::seconds kSmokeDeadline{150};
constexpr std::chrono::seconds kNoRuntimeDeadline{30};

std::filesystem::path cache_dir() {
  if (const char* cache = std::getenv("DHR_CACHE")) return cache;
  const char* home = std::getenv("HOME");
  return std::filesystem::path(home != nullptr ? home : "/root") / ".cache" / "dhr-xr";
}

bool monado_installed() { return std::filesystem::exists(cache_dir() / "env.sh"); }

#define SKIP_WITHOUT_MONADO()                                                              \
  do {                                                                                     \
    if (!monado_installed()) {                                                             \
      GTEST_SKIP() << "Monado is not set up (" << (cache_dir() / "env.sh").string()        \
                   << " missing): run scripts/setup";                                      \
    }                                                                                      \
  } while (0)

// Parses the smoke run's last stdout line; adds a failure and returns null when it is not JSON.
nlohmann::json parse_report(const ChildResult& child) {
  const std::string line = last_line(child.out);
  nlohmann::json report = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (report.is_discarded() || !report.is_object()) {
    ADD_FAILURE() << "last stdout line is not a JSON object: '" << line << "'\nstderr tail: "
                  << child.err.substr(child.err.size() > 3000 ? child.err.size() - 3000 : 0);
    return nullptr;
  }
  return report;
}

bool finite_vec3(const nlohmann::json& v) {
  if (!v.is_array() || v.size() != 3) return false;
  for (const auto& x : v) {
    if (!x.is_number() || !std::isfinite(x.get<double>())) return false;
  }
  return true;
}

ChildSpec smoke_spec(std::vector<std::string> client_args) {
  ChildSpec spec;
  spec.argv = {DHR_WITH_MONADO, DHR_XRCLIENT_EXE, "--smoke"};
  spec.argv.insert(spec.argv.end(), client_args.begin(), client_args.end());
  // DHR_VK_DEVICE / VK_DRIVER_FILES pass through: lavapipe by default, DHR_VK_DEVICE=gpu on a GPU.
  spec.deadline = kSmokeDeadline;
  return spec;
}

TEST(XrSmoke, ReachesFocusedRendersAndExitsClean) {
  SKIP_WITHOUT_MONADO();
  const ChildResult child = run_child(smoke_spec({"--frames", "300"}));
  ASSERT_TRUE(child.started) << child.err;
  ASSERT_FALSE(child.killed_at_deadline) << "the smoke run hung; stderr:\n" << child.err;
  EXPECT_EQ(child.exit_code, 0) << child.err;
  const nlohmann::json report = parse_report(child);
  ASSERT_FALSE(report.is_null());

  EXPECT_EQ(report.value("exit", ""), "clean");
  EXPECT_TRUE(report.value("reached_focused", false));
  EXPECT_GE(report.value("frames", 0), 300);
  EXPECT_GE(report.value("frames_presented", 0), 300);
  EXPECT_GT(report.value("fps", 0.0), 0.0);
  EXPECT_NE(report.value("runtime", "").find("Monado"), std::string::npos);
  EXPECT_FALSE(report.value("system", "").empty());

  const nlohmann::json& states = report.at("states");
  ASSERT_TRUE(states.is_array());
  ASSERT_FALSE(states.empty());
  EXPECT_EQ(states.back(), "EXITING");
  for (const char* state : {"READY", "FOCUSED", "STOPPING"}) {
    EXPECT_NE(std::find(states.begin(), states.end(), state), states.end()) << state;
  }

  const nlohmann::json& sizes = report.at("eye_size");
  ASSERT_EQ(sizes.size(), 2u);
  for (const auto& size : sizes) {
    EXPECT_GT(size.at(0).get<int>(), 0);
    EXPECT_GT(size.at(1).get<int>(), 0);
  }

  const nlohmann::json& ranges = report.at("pose_range");
  ASSERT_TRUE(ranges.is_array());
  ASSERT_EQ(ranges.size(), 2u);
  for (size_t eye = 0; eye < 2; ++eye) {
    const nlohmann::json& range = ranges[eye];
    ASSERT_TRUE(range.is_object()) << "no valid pose for eye " << eye;
    ASSERT_TRUE(finite_vec3(range.at("min"))) << range.dump();
    ASSERT_TRUE(finite_vec3(range.at("max"))) << range.dump();
    // The simulated head wobbles: over 300 frames each eye must have moved.
    double extent = 0.0;
    for (size_t axis = 0; axis < 3; ++axis) {
      const double span = range["max"][axis].get<double>() - range["min"][axis].get<double>();
      EXPECT_GE(span, 0.0) << "eye " << eye << " axis " << axis;
      extent = std::max(extent, span);
    }
    EXPECT_GT(extent, 1e-3) << "eye " << eye << " did not move: " << range.dump();
  }

  const nlohmann::json& ipd = report.at("ipd_m");
  ASSERT_TRUE(ipd.is_number());
  EXPECT_NEAR(ipd.get<double>(), kExpectedIpdM, kIpdToleranceM);
}

TEST(XrSmoke, SigintShutsTheSessionDownCleanly) {
  SKIP_WITHOUT_MONADO();
  // Far more frames than will run: only the signal ends this session.
  ChildSpec spec = smoke_spec({"--frames", "1000000", "--timeout", "100"});
  bool sent = false;
  spec.on_output = [&sent](pid_t pid, const std::string&, const std::string& err) {
    if (!sent && err.find("-> FOCUSED") != std::string::npos) {
      // with-monado execs the client, so pid is the client itself.
      kill(pid, SIGINT);
      sent = true;
    }
  };
  const ChildResult child = run_child(spec);
  ASSERT_TRUE(child.started) << child.err;
  ASSERT_FALSE(child.killed_at_deadline) << "the client did not stop on SIGINT; stderr:\n" << child.err;
  ASSERT_TRUE(sent) << "the session never reached FOCUSED; stderr:\n" << child.err;
  EXPECT_EQ(child.term_signal, 0);
  EXPECT_EQ(child.exit_code, 0) << child.err;
  const nlohmann::json report = parse_report(child);
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report.value("exit", ""), "clean");
  EXPECT_EQ(report.value("signal", 0), SIGINT);
  const nlohmann::json& states = report.at("states");
  ASSERT_FALSE(states.empty());
  EXPECT_EQ(states.back(), "EXITING");
}

TEST(XrNoRuntime, MissingManifestFailsFastWithOneLineError) {
  ChildSpec spec;
  spec.argv = {DHR_XRCLIENT_EXE, "--smoke"};
  spec.env["XR_RUNTIME_JSON"] = "/nonexistent/dhr-xr-test/openxr_missing_runtime.json";
  spec.deadline = kNoRuntimeDeadline;
  const ChildResult child = run_child(spec);
  ASSERT_TRUE(child.started) << child.err;
  ASSERT_FALSE(child.killed_at_deadline) << "the client hung without a runtime";
  EXPECT_EQ(child.term_signal, 0) << "crashed instead of reporting an error";
  EXPECT_NE(child.exit_code, 0);
  EXPECT_EQ(last_line(child.out), "") << "no JSON report without a session";
  const std::string error_line = last_line(child.err);
  EXPECT_NE(error_line.find("no OpenXR runtime found"), std::string::npos) << child.err;
  EXPECT_NE(error_line.find("XR_RUNTIME_JSON"), std::string::npos) << error_line;
}

TEST(XrNoRuntime, WithMonadoExplainsAMissingSetup) {
  ChildSpec spec;
  spec.argv = {DHR_WITH_MONADO, DHR_XRCLIENT_EXE, "--smoke"};
  spec.env["DHR_CACHE"] = "/nonexistent/dhr-xr-test-cache";
  spec.deadline = kNoRuntimeDeadline;
  const ChildResult child = run_child(spec);
  ASSERT_TRUE(child.started) << child.err;
  EXPECT_NE(child.exit_code, 0);
  EXPECT_NE(last_line(child.err).find("run scripts/setup"), std::string::npos) << child.err;
}

TEST(XrCli, UnknownDeviceIsRejected) {
  ChildSpec spec;
  spec.argv = {DHR_XRCLIENT_EXE, "--smoke", "--vk-device", "quantum"};
  spec.deadline = kNoRuntimeDeadline;
  const ChildResult child = run_child(spec);
  ASSERT_TRUE(child.started) << child.err;
  EXPECT_EQ(child.term_signal, 0);
  EXPECT_NE(child.exit_code, 0);
  EXPECT_NE(child.err.find("--vk-device"), std::string::npos) << child.err;
}

}  // namespace
}  // namespace dhr::test
