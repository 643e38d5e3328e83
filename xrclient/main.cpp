// dhr-xrclient: the DHR-XR headset client. For now only the smoke mode, which proves the
// OpenXR + Vulkan path end to end (see docs/xr-runtimes.md).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string>

#include "core/log.hpp"
#include "exit_signal.hpp"
#include "smoke.hpp"

namespace {

constexpr int kExitError = 1;        // setup failed: no runtime, no HMD, session refused, no device
constexpr int kExitUsage = 2;        // nothing to do
constexpr int kExitNotClean = 3;     // the session ended, but not cleanly (timeout, loss, frame error)

int run_smoke_mode(const dhr::SmokeOptions& options) {
  const dhr::SmokeReport report = dhr::run_smoke(options);
  std::fflush(stderr);
  std::printf("%s\n", dhr::smoke_report_json(report).c_str());
  std::fflush(stdout);
  if (report.exit != "clean") {
    std::fprintf(stderr, "error: smoke session did not end cleanly (exit: %s)\n", report.exit.c_str());
    return kExitNotClean;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"DHR-XR headset client"};
  bool smoke = false;
  dhr::SmokeOptions smoke_options;
  std::string vk_device = "auto";
  std::string swapchain_encoding = "srgb";
  app.add_flag("--smoke", smoke,
               "Run a smoke session: clear both eyes for --frames frames, print one JSON line");
  app.add_option("--frames", smoke_options.frames, "Frames to run in --smoke mode")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--timeout", smoke_options.timeout_s,
                 "Wall-clock cap in seconds for the frame phase of --smoke")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--vk-device", vk_device, "Vulkan device: auto | gpu | lavapipe")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "gpu", "lavapipe", "cpu"}));
  app.add_option("--swapchain-format", swapchain_encoding,
                 "Preferred swapchain colour encoding: srgb | unorm")
      ->capture_default_str()
      ->check(CLI::IsMember({"srgb", "unorm"}));
  CLI11_PARSE(app, argc, argv);

  if (!smoke) {
    std::fprintf(stderr, "error: nothing to do: pass --smoke (see --help)\n");
    return kExitUsage;
  }
  try {
    smoke_options.device = dhr::vk::parse_device_preference(vk_device);
    smoke_options.color_encoding =
        swapchain_encoding == "unorm" ? dhr::xr::ColorEncoding::kUnorm : dhr::xr::ColorEncoding::kSrgb;
    dhr::install_exit_signal_handlers();
    return run_smoke_mode(smoke_options);
  } catch (const std::exception& e) {
    // One line, last on stderr: the loader and the runtime may have printed their own before.
    std::fflush(stdout);
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitError;
  }
}
