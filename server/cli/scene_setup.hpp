// Loading the scene the command line names, with the checks every mode shares.
#pragma once
#include "scene/scene.hpp"
#include "server_options.hpp"

#include <optional>
#include <string>

namespace dhr::server::cli {

// Loads options.scene_path, applies --lights, and rejects scenes nothing can be traced in (no
// triangles). std::nullopt with a one-line message otherwise.
std::optional<Scene> load_server_scene(const ServerOptions& options, std::string* out_error);

// The warning for a backend that traces an animated scene at its rest pose.
std::string animations_not_played(const Scene& scene, TracerBackend backend);

// Prints "dhr-server: MESSAGE" on stderr and returns exit_code::kUsage (2): an input the command line names is
// unusable (cli/exit_codes.hpp).
int fail_setup(const std::string& message);
// The same for a run that failed (exit_code::kFailure, 1): a tracer that cannot be created, a socket that cannot
// be bound, a file that cannot be written.
int fail_run(const std::string& message);

}  // namespace dhr::server::cli
