// The scene both ends of a session work from: the file, loaded and checked non-empty, with a --lights
// override applied. dhr-server traces it and names its scene_content_hash in the Welcome; dhr-xrclient loads
// it the same way and refuses a Welcome that names another hash (docs/protocol.md, "Handshake and session").
#pragma once
#include "scene/scene.hpp"

#include <optional>
#include <string>
#include <string_view>

namespace dhr {

// std::nullopt with a one-line `out_error` ("<file>: <problem>" or "--lights: <problem>") when the file cannot
// be loaded, has no triangles, or the light specs (parse_light_specs) are unusable. Empty `lights_spec`: the
// file's own lights.
std::optional<Scene> load_session_scene(const std::string& path, std::string_view lights_spec,
                                        std::string* out_error);

}  // namespace dhr
