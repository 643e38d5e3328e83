// dhr-server: loads a scene and traces per-eye light visibility. Modes: --check, --snapshot DIR.
// Serving clients over UDP (--port) arrives with the transport issue as one more Mode and run_* function.
#include "check_command.hpp"
#include "server_options.hpp"
#include "snapshot_command.hpp"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  using namespace dhr::server::cli;
  ServerOptions options;
  if (auto exit_code = parse_server_options(argc, argv, options)) return *exit_code;
  try {
    switch (options.mode) {
      case Mode::kCheck: return run_check(options);
      case Mode::kSnapshot: return run_snapshot(options);
      case Mode::kNone: break;
    }
    std::fprintf(stderr,
                 "dhr-server: nothing to do: give --check or --snapshot DIR (serving clients arrives with the "
                 "transport; see --help)\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dhr-server: %s\n", e.what());
    return 1;
  }
}
