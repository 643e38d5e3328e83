// The two ways dhr-xrclient renders: offscreen (a trace or the scripted orbit, PNGs) and under OpenXR.
// Each prints the summary JSON as the last stdout line and returns the process exit code; setup failures
// throw with a one-line message.
#pragma once
#include "app/client_options.hpp"

namespace dhr::client {

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;      // setup failed
inline constexpr int kExitNotClean = 3;   // the run ended, but not cleanly (GPU error, session error, timeout)

int run_offscreen(const ClientOptions& options);
int run_openxr(const ClientOptions& options);

}  // namespace dhr::client
