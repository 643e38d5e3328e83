#include "check_command.hpp"

#include "scene/scene.hpp"
#include "scene_setup.hpp"
#include "cli/exit_codes.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>

namespace dhr::server::cli {

int run_check(const ServerOptions& options) {
  std::string error;
  std::optional<Scene> scene = load_server_scene(options, &error);
  if (!scene) return fail_setup(error);
  const nlohmann::ordered_json report = {{"scene", scene->source},
                                 {"meshes", scene->meshes.size()},
                                 {"triangles", scene->triangle_count},
                                 {"lights", scene->lights.size()},
                                 {"default_lights", scene->default_lights},
                                 {"materials", scene->materials.size()},
                                 {"images", scene->images.size()},
                                 {"warnings", scene->warnings}};
  // Replace invalid UTF-8 (from file names or glTF strings) instead of throwing.
  std::printf("%s\n", report.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace).c_str());
  return exit_code::kOk;
}

}  // namespace dhr::server::cli
