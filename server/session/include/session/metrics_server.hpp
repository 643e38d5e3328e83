// The HTTP endpoint of dhr-server --metrics-port (civetweb, from Debian): GET /metrics answers the service's
// statistics in the Prometheus text format (metrics_text.hpp), anything else 404. Two civetweb threads.
#pragma once
#include <cstdint>
#include <functional>
#include <string>

struct mg_context;
struct mg_connection;

namespace dhr::server {

class MetricsServer {
 public:
  using Source = std::function<std::string()>;  // the body of /metrics, called on a civetweb thread
  // Listens on bind_address:port (port >= 1). Throws std::runtime_error when it cannot.
  MetricsServer(const std::string& bind_address, uint16_t port, Source source);
  ~MetricsServer();
  MetricsServer(const MetricsServer&) = delete;
  MetricsServer& operator=(const MetricsServer&) = delete;

 private:
  static int handle(::mg_connection* conn, void* self);
  Source source_;
  mg_context* context_ = nullptr;
};

}  // namespace dhr::server
