#include "session/metrics_server.hpp"

#include <civetweb.h>

#include <cstring>
#include <mutex>
#include <stdexcept>

namespace dhr::server {

MetricsServer::MetricsServer(const std::string& bind_address, uint16_t port, Source source)
    : source_(std::move(source)) {
  if (port == 0) throw std::runtime_error("--metrics-port: needs a port number (1..65535)");
  static std::once_flag once;
  std::call_once(once, [] { mg_init_library(0); });
  const bool ipv6 = bind_address.find(':') != std::string::npos;
  const std::string ports = (ipv6 ? "[" + bind_address + "]" : bind_address) + ":" + std::to_string(port);
  const char* options[] = {"listening_ports", ports.c_str(), "num_threads", "2", nullptr};
  mg_callbacks callbacks{};
  callbacks.log_message = [](const mg_connection*, const char*) { return 1; };  // errors come back as a throw
  context_ = mg_start(&callbacks, this, options);
  if (context_ == nullptr) {
    throw std::runtime_error("--metrics-port: cannot listen on " + ports + " (in use, or a bad address)");
  }
  mg_set_request_handler(context_, "/metrics", &MetricsServer::handle, this);
}

MetricsServer::~MetricsServer() {
  if (context_ != nullptr) mg_stop(context_);
}

int MetricsServer::handle(mg_connection* conn, void* self) {
  const mg_request_info* request = mg_get_request_info(conn);
  if (request == nullptr || std::strcmp(request->request_method, "GET") != 0 ||
      std::strcmp(request->local_uri, "/metrics") != 0) {
    mg_send_http_error(conn, 404, "%s", "not found: GET /metrics\n");
    return 404;
  }
  const std::string body = static_cast<MetricsServer*>(self)->source_();
  mg_printf(conn,
            "HTTP/1.1 200 OK\r\nContent-Type: text/plain; version=0.0.4; charset=utf-8\r\n"
            "Content-Length: %zu\r\nConnection: close\r\n\r\n",
            body.size());
  mg_write(conn, body.data(), body.size());
  return 200;
}

}  // namespace dhr::server
