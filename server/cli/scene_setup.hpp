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

// Prints "dhr-server: MESSAGE" on stderr and returns 2, the exit code of an unusable setup.
int fail_setup(const std::string& message);

}  // namespace dhr::server::cli
