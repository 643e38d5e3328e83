// The one table of exit codes every DHR-XR executable uses (docs/exit-codes.md lists it with what each
// executable returns it for; tests/integration/exit_codes.sh checks each executable against it).
#pragma once
#include <stdexcept>

namespace dhr::exit_code {

inline constexpr int kOk = 0;
// The run started and failed: a GPU or runtime error, a file that cannot be written, a server that cannot be
// reached, a benchmark whose measurement failed.
inline constexpr int kFailure = 1;
// The command line is wrong, or an input it names is unusable (a scene, trace, key or views file that is
// missing or malformed, a bad address): nothing ran.
inline constexpr int kUsage = 2;
// The run ended, but not cleanly (a session error, a timeout, frames lost to GPU errors).
inline constexpr int kNotClean = 3;
// The server refused the key, requires one, or did not authenticate.
inline constexpr int kAuthentication = 4;
// The server traces another scene than the client's (its Welcome names another scene hash).
inline constexpr int kSceneMismatch = 5;
// ctest's SKIP_RETURN_CODE: a test script that cannot run here (no root, no data) returns it.
inline constexpr int kTestSkipped = 77;
// A watchdog ended a run that hung past its wall-clock cap (as timeout(1)).
inline constexpr int kWatchdog = 124;

}  // namespace dhr::exit_code

namespace dhr::cli {

// Thrown where an input the command line names turns out unusable (a scene, trace, key or views file, an
// address); an executable's main maps it to exit_code::kUsage.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace dhr::cli
