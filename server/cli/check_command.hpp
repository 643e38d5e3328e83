// dhr-server --check: load and validate a scene, print one JSON line.
#pragma once
#include "server_options.hpp"

namespace dhr::server::cli {

// Exit code: 0 for a usable scene (warnings allowed), 2 with a one-line error on stderr otherwise.
int run_check(const ServerOptions& options);

}  // namespace dhr::server::cli
