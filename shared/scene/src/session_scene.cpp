#include "scene/session_scene.hpp"

#include <string>

namespace dhr {
namespace {

// Errors are printed as one line (loader messages may carry several).
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace

std::string describe_animations(const Scene& scene) {
  return std::to_string(scene.animation.clips.size()) + " animation(s), " +
         std::to_string(scene.animation.tracks.size()) + " track(s)";
}

std::optional<Scene> load_session_scene(const std::string& path, std::string_view lights_spec,
                                        std::string* out_error) {
  SceneLoadResult loaded = load_scene(path);
  if (!loaded) {
    *out_error = loaded.error.empty() ? path + ": cannot load the scene" : one_line(loaded.error);
    return std::nullopt;
  }
  Scene scene = std::move(*loaded.scene);
  if (scene.triangle_count == 0) {
    *out_error = path + ": the scene has no triangles";
    return std::nullopt;
  }
  if (!lights_spec.empty()) {
    std::string error;
    auto lights = parse_light_specs(lights_spec, &error);
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

}  // namespace dhr
