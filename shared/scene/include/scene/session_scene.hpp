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

// Which end loads the scene: what it says about the scene's animations differs. The server plays them on the
// scene clock (it traces each frame at its pose's scene time; its tracer says when it cannot, see dhr-server);
// the client does not draw them yet, and says so in a warning.
enum class SessionSide : uint8_t { kClient, kServer };

// std::nullopt with a one-line `out_error` ("<file>: <problem>" or "--lights: <problem>") when the file cannot
// be loaded, has no triangles, or the light specs (parse_light_specs) are unusable. Empty `lights_spec`: the
// file's own lights. An animated scene loaded by the client gets a warning that it is drawn at its rest pose.
std::optional<Scene> load_session_scene(const std::string& path, std::string_view lights_spec,
                                        std::string* out_error, SessionSide side = SessionSide::kClient);

// "N animation(s), M track(s)": the scene's animations, for log lines.
std::string describe_animations(const Scene& scene);

}  // namespace dhr
