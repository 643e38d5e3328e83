// JSON form of ServiceStats: dhr-server's final stats line and dhr-eval reports.
#pragma once
#include "session/visibility_service.hpp"

#include <nlohmann/json.hpp>

namespace dhr::server {

// Every counter by its field name; decode_errors as {"truncated": n, ...} with non-zero codes only.
nlohmann::ordered_json to_json(const ServiceStats& stats);

}  // namespace dhr::server
