// The two ways dhr-xrclient renders: offscreen (a trace or the scripted orbit, PNGs) and under OpenXR.
// Each prints the summary JSON as the last stdout line and returns the process exit code; setup failures
// throw with a one-line message.
#pragma once
#include "app/client_options.hpp"

#include <stdexcept>

namespace dhr::client {

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;      // setup failed
inline constexpr int kExitNotClean = 3;   // the run ended, but not cleanly (GPU error, session error, timeout)
inline constexpr int kExitAuth = 4;       // the server refused the key (or requires one), or did not authenticate

// Thrown by the setup when the handshake failed on authentication (exit code kExitAuth).
struct AuthenticationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

int run_offscreen(const ClientOptions& options);
int run_openxr(const ClientOptions& options);

}  // namespace dhr::client
