// dhr-server --port P: load the scene, build the tracer, serve clients (session/serve.hpp) until a signal
// or --max-seconds.
#pragma once
#include "server_options.hpp"

namespace dhr::server::cli {

// 0 after a clean stop, 2 for an unusable scene, address or tracer (one line on stderr).
int run_serve_command(const ServerOptions& options);

}  // namespace dhr::server::cli
