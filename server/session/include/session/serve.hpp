// run_serve: dhr-server's serving mode. A ServerEndpoint on --bind:--port feeds VisibilityService from its
// socket thread; a worker thread traces pending poses; the calling thread ticks (timeouts, heartbeats) and
// prints a short stats line to stderr at most once per second. Optional impairment of everything sent
// (ImpairedSender, the --net-* options). SIGINT / SIGTERM (or max_seconds) stop it cleanly: Bye(shutdown)
// to every session, threads joined, one JSON line of ServiceStats on stdout.
#pragma once
#include "net/impairment.hpp"
#include "session/visibility_service.hpp"

#include <cstdint>
#include <string>

namespace dhr::server {

struct ServeOptions {
  std::string bind_address = "0.0.0.0";
  uint16_t port = 0;          // 0: ephemeral (the "listening on" line names the port)
  double max_seconds = 0.0;   // > 0: stop by itself after this long (scripts, tests)
  net::ImpairmentParams impairment;  // applied to every datagram the server sends
  ServiceConfig service;
  int64_t tick_interval_ns = 20 * net::kNsPerMs;
  bool handle_signals = true;  // SIGINT / SIGTERM stop the loop (restored on return)
  uint16_t metrics_port = 0;   // > 0: GET /metrics on bind_address:metrics_port (Prometheus text)
};

// Serves until a signal or max_seconds. Prints "listening on ADDR:PORT" to stderr once bound. Returns the
// exit code (0 after a clean stop). Throws std::runtime_error when the address cannot be bound or the
// impairment parameters are invalid.
int run_serve(const ServeOptions& options, VisibilityTracer& tracer);

}  // namespace dhr::server
