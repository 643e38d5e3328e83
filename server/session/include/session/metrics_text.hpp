// The service's statistics in the Prometheus text exposition format (version 0.0.4), for
// dhr-server --metrics-port (docs/server.md, "Metrics"): sessions, frames traced, rays, bytes sent,
// datagrams dropped by reason, authentication failures, and the trace and response time histograms.
#pragma once
#include <string>

#include "session/visibility_service.hpp"

namespace dhr::server {

std::string prometheus_text(const ServiceStats& stats);

}  // namespace dhr::server
