#include "scene_setup.hpp"

#include "cli/exit_codes.hpp"
#include "scene/session_scene.hpp"

#include <cstdio>

namespace dhr::server::cli {

std::optional<Scene> load_server_scene(const ServerOptions& options, std::string* out_error) {
  return load_session_scene(options.scene_path, options.lights, out_error);
}

int fail_setup(const std::string& message) {
  std::fprintf(stderr, "dhr-server: %s\n", message.c_str());
  return exit_code::kUsage;
}

int fail_run(const std::string& message) {
  std::fprintf(stderr, "dhr-server: %s\n", message.c_str());
  return exit_code::kFailure;
}

}  // namespace dhr::server::cli
