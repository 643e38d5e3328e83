#include "check_command.hpp"

#include "scene/scene.hpp"
#include "scene_setup.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>

namespace dhr::server::cli {

int run_check(const ServerOptions& options) {
  std::string error;
  std::optional<Scene> scene = load_server_scene(options, &error);
  if (!scene) {
    std::fprintf(stderr, "dhr-server: %s\n", error.c_str());
    return 2;
  }
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
  return 0;
}

}  // namespace dhr::server::cli
