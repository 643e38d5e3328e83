// JSON forms of the tracer statistics, for the CLI's reports and the benchmarks.
#pragma once
#include "trace/visibility_tracer.hpp"

#include <nlohmann/json.hpp>

namespace dhr::server {

nlohmann::ordered_json to_json(const TraceStats& stats);
nlohmann::ordered_json to_json(const AccelStats& stats);
nlohmann::ordered_json to_json(const SkipOptions& skip);

}  // namespace dhr::server
