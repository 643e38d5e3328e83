#include "scene_setup.hpp"

#include "cli/exit_codes.hpp"
#include "scene/session_scene.hpp"

#include <cstdio>

namespace dhr::server::cli {

std::optional<Scene> load_server_scene(const ServerOptions& options, std::string* out_error) {
  // Both backends play the animations on the scene clock (a tracer that does not is named at start: serve_command).
  return load_session_scene(options.scene_path, options.lights, out_error);
}

std::string animations_not_played(const Scene& scene, TracerBackend backend) {
  return describe_animations(scene) + " not played by the " + tracer_backend_name(backend) +
         " backend: it traces the scene at its rest pose";
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
