// For the benchmarks that parse their few options by hand: --help (or -h) anywhere on the command line asks for
// the usage text, which goes to stdout with exit code 0 (exit_codes.hpp), as CLI11's --help does elsewhere.
#pragma once
#include <string_view>

namespace dhr::cli {

inline bool asks_for_help(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "--help" || a == "-h") return true;
  }
  return false;
}

}  // namespace dhr::cli
