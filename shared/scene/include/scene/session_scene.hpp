// The scene both ends of a session work from: the file, loaded and checked non-empty, with a --lights
// override applied. dhr-server traces it and names its scene_content_hash in the Welcome; dhr-xrclient loads
// it the same way and refuses a Welcome that names another hash (docs/protocol.md, "Handshake and session").
#pragma once
#include "scene/scene.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace dhr {

// std::nullopt with a one-line `out_error` ("<file>: <problem>" or "--lights: <problem>") when the file cannot
// be loaded, has no triangles, or the light specs (parse_light_specs) are unusable. Empty `lights_spec`: the
// file's own lights. Both ends play its animations on the scene clock (DESIGN 5b): nothing to warn about here
// (dhr-server says when its tracer cannot move the scene).
std::optional<Scene> load_session_scene(const std::string& path, std::string_view lights_spec,
                                        std::string* out_error);

// "N animation(s), M track(s)": the scene's animations, for log lines.
std::string describe_animations(const Scene& scene);

}  // namespace dhr
