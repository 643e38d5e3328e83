// Runs a child process (posix_spawn) with a modified environment, capturing stdout and stderr,
// with a hard deadline after which the child is killed (so a hanging client fails the test
// instead of hanging ctest).
#pragma once
#include <sys/types.h>

#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace dhr::test {

struct ChildSpec {
  std::vector<std::string> argv;
  // Values to set (std::nullopt: remove the variable) on top of this process's environment.
  std::map<std::string, std::optional<std::string>> env;
  std::chrono::milliseconds deadline{std::chrono::seconds(120)};
  // Called whenever new output arrived, with everything captured so far.
  std::function<void(pid_t pid, const std::string& out, const std::string& err)> on_output;
};

struct ChildResult {
  bool started = false;
  bool killed_at_deadline = false;
  int exit_code = -1;    // when it exited normally
  int term_signal = 0;   // when a signal ended it
  std::string out;
  std::string err;
  double seconds = 0.0;  // wall time until it ended
};

ChildResult run_child(const ChildSpec& spec);

// The last non-empty line of text (without the newline), "" when none.
std::string last_line(const std::string& text);

}  // namespace dhr::test
