#include "check_command.hpp"

#include "scene/scene.hpp"
#include "layout_report.hpp"
#include "scene_setup.hpp"
#include "cli/exit_codes.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>

namespace dhr::server::cli {

int run_check(const ServerOptions& options) {
  std::string error;
  std::optional<Scene> scene = load_server_scene(options, &error);
  if (!scene) return fail_setup(error);
  // Each light as it will be traced: its type and extent for people, its spec string (--lights syntax) for tools.
  nlohmann::ordered_json light_details = nlohmann::ordered_json::array();
  for (const SceneLight& light : scene->lights) {
    light_details.push_back({{"name", light.name},
                             {"type", light_type_name(light.type)},
                             {"extent", describe_light_extent(light)},
                             {"spec", format_light_spec(light)}});
  }
  const nlohmann::ordered_json report = {{"scene", scene->source},
                                 {"meshes", scene->meshes.size()},
                                 {"triangles", scene->triangle_count},
                                 {"lights", scene->lights.size()},
                                 {"light_details", light_details},
                                 {"mask_layout", layout_json(scene->lights)},
                                 {"default_lights", scene->default_lights},
                                 {"materials", scene->materials.size()},
                                 {"images", scene->images.size()},
                                 {"warnings", scene->warnings}};
  // Replace invalid UTF-8 (from file names or glTF strings) instead of throwing.
  std::printf("%s\n", report.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace).c_str());
  return exit_code::kOk;
}

}  // namespace dhr::server::cli
