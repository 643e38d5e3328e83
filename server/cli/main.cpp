// dhr-server: loads a scene and traces per-eye light visibility. Modes: --check, --snapshot DIR, and
// --port P (serve clients over UDP).
#include "check_command.hpp"
#include "serve_command.hpp"
#include "server_options.hpp"
#include "snapshot_command.hpp"
#include "cli/exit_codes.hpp"
#include "secure/key.hpp"

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
      case Mode::kServe: return run_serve_command(options);
      case Mode::kGenKey: {
        if (const auto error = dhr::secure::generate_key_file(options.gen_key_path)) {
          std::fprintf(stderr, "dhr-server: --gen-key: %s\n", error->c_str());
          return dhr::exit_code::kUsage;
        }
        std::fprintf(stderr, "dhr-server: wrote a new deployment key to %s (give it to the server and its "
                             "clients with --key-file)\n", options.gen_key_path.c_str());
        return dhr::exit_code::kOk;
      }
      case Mode::kNone: break;
    }
    std::fprintf(stderr,
                 "dhr-server: nothing to do: give --check, --snapshot DIR, --port P or --gen-key FILE (see --help)\n");
    return dhr::exit_code::kUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dhr-server: %s\n", e.what());
    return dhr::exit_code::kFailure;
  }
}
