#include "scene_setup.hpp"

#include <cstdio>

namespace dhr::server::cli {
namespace {

// Errors are printed as one line (loader messages may carry several).
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace

std::optional<Scene> load_server_scene(const ServerOptions& options, std::string* out_error) {
  SceneLoadResult loaded = load_scene(options.scene_path);
  if (!loaded) {
    *out_error = loaded.error.empty() ? options.scene_path + ": cannot load the scene" : one_line(loaded.error);
    return std::nullopt;
  }
  Scene scene = std::move(*loaded.scene);
  if (scene.triangle_count == 0) {
    *out_error = options.scene_path + ": the scene has no triangles";
    return std::nullopt;
  }
  if (!options.lights.empty()) {
    std::string error;
    auto lights = parse_light_specs(options.lights, &error);
    if (!lights) {
      *out_error = "--lights: " + one_line(error);
      return std::nullopt;
    }
    if (auto err = set_scene_lights(scene, std::move(*lights))) {
      *out_error = "--lights: " + *err;
      return std::nullopt;
    }
  }
  return scene;
}

int fail_setup(const std::string& message) {
  std::fprintf(stderr, "dhr-server: %s\n", message.c_str());
  return 2;
}

}  // namespace dhr::server::cli
