// The two ways dhr-xrclient renders: offscreen (a trace or the scripted orbit, PNGs) and under OpenXR.
// Each prints the summary JSON as the last stdout line and returns the process exit code; setup failures
// throw with a one-line message.
#pragma once
#include "app/client_options.hpp"
#include "cli/exit_codes.hpp"

#include <stdexcept>

namespace dhr::client {

// The project's exit-code table (cli/exit_codes.hpp, docs/exit-codes.md).
inline constexpr int kExitOk = exit_code::kOk;
inline constexpr int kExitError = exit_code::kFailure;        // setup or the run failed
inline constexpr int kExitBadInput = exit_code::kUsage;       // a scene, trace, key file or address unusable
inline constexpr int kExitNotClean = exit_code::kNotClean;    // the run ended, but not cleanly
inline constexpr int kExitAuth = exit_code::kAuthentication;  // the server refused the key, or did not authenticate
inline constexpr int kExitSceneMismatch = exit_code::kSceneMismatch;  // the server traces another scene

// Thrown by the setup when an input the command line names is unusable (exit code kExitBadInput).
using InputError = cli::InputError;
// Thrown by the setup when the handshake failed on authentication (exit code kExitAuth).
struct AuthenticationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// Thrown by the setup when the server's Welcome names another scene (exit code kExitSceneMismatch).
struct SceneMismatchError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

int run_offscreen(const ClientOptions& options);
int run_openxr(const ClientOptions& options);

}  // namespace dhr::client
