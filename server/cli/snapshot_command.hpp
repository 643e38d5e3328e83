// dhr-server --snapshot DIR: trace the left eye of each camera bookmark and write PNGs + JSON lines.
#pragma once
#include "server_options.hpp"

namespace dhr::server::cli {

// Per bookmark <name>: DIR/<name>_light<i>.png (white = visible) for every light and DIR/<name>_shaded.png,
// and one JSON line on stdout with the statistics. Exit code 0, or 2 with a one-line error on stderr.
int run_snapshot(const ServerOptions& options);

// Bookmark name -> safe file name part ([A-Za-z0-9_-], others replaced by '_'; empty -> "camera").
std::string file_safe_name(const std::string& name);

}  // namespace dhr::server::cli
