// The mask layout a soft-capable client gets (docs/protocol.md, "Mask layout"), for the serving line and
// --check: which lights get Gray-coded level fields, at which bits, and which soft lights were demoted to one bit.
#pragma once
#include "scene/scene.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace dhr::server::cli {

// {"bits": total bits per mask, "mask_bits": 8/16/32, "soft_lights": [{"name", "first_bit", "bits"}...],
//  "demoted": [names]} for all the scene's lights (up to 32); with more, the light slots they share: {"bits",
//  "mask_bits", "light_slots", "light_slots_describe", "lights_without_slot": [names]}.
nlohmann::ordered_json layout_json(const std::vector<SceneLight>& lights);
// One line: "soft levels for clients that offer them: 'a' bits 0-2, 'b' bits 3-5; 7 bits per mask (8-bit masks)"
// or "no light with an extent: one bit per light".
std::string layout_line(const std::vector<SceneLight>& lights);
// Names of soft lights that got one bit for lack of room (empty when none).
std::vector<std::string> demoted_lights(const std::vector<SceneLight>& lights);

}  // namespace dhr::server::cli
