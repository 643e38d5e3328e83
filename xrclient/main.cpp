// dhr-xrclient: the DHR-XR headset client (docs/client.md). Options: app/client_options.hpp; the runs:
// app/offscreen_run.cpp, app/openxr_run.cpp; --smoke: smoke.cpp.
#include <cstdio>
#include <exception>

#include "app/client_options.hpp"
#include "app/run_modes.hpp"
#include "exit_signal.hpp"
#include "smoke.hpp"

namespace {

constexpr int kExitSmokeNotClean = 3;  // the smoke session ended, but not cleanly

int run_smoke_mode(const dhr::SmokeOptions& options) {
  const dhr::SmokeReport report = dhr::run_smoke(options);
  std::fflush(stderr);
  std::printf("%s\n", dhr::smoke_report_json(report).c_str());
  std::fflush(stdout);
  if (report.exit != "clean") {
    std::fprintf(stderr, "error: smoke session did not end cleanly (exit: %s)\n", report.exit.c_str());
    return kExitSmokeNotClean;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  dhr::client::ClientOptions options;
  int exit_code = 0;
  if (dhr::client::parse_client_options(argc, argv, options, &exit_code) == dhr::client::ParseOutcome::kExit) {
    return exit_code;
  }
  try {
    dhr::install_exit_signal_handlers();
    if (options.smoke) return run_smoke_mode(options.smoke_options);
    if (!options.offscreen.empty()) return dhr::client::run_offscreen(options);
    return dhr::client::run_openxr(options);
  } catch (const dhr::client::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return dhr::client::kExitBadInput;
  } catch (const dhr::client::AuthenticationError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return dhr::client::kExitAuth;
  } catch (const dhr::client::SceneMismatchError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return dhr::client::kExitSceneMismatch;
  } catch (const std::exception& e) {
    // One line, last on stderr: the loader and the runtime may have printed their own before.
    std::fflush(stdout);
    std::fprintf(stderr, "error: %s\n", e.what());
    return dhr::client::kExitError;
  }
}
