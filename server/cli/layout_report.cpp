#include "layout_report.hpp"

#include "scene/light_slots.hpp"
#include "visibility/visibility_layout.hpp"

#include <algorithm>

namespace dhr::server::cli {
namespace {

VisibilityLayout soft_layout(const std::vector<SceneLight>& lights) {
  bool soft[kMaxLights] = {};
  const size_t n = std::min<size_t>(lights.size(), kMaxLights);
  for (size_t i = 0; i < n; ++i) soft[i] = lights[i].has_extent();
  return VisibilityLayout::for_lights(std::span<const bool>(soft, n));
}

std::string light_name(const std::vector<SceneLight>& lights, uint32_t i) {
  return lights[i].name.empty() ? "light " + std::to_string(i) : lights[i].name;
}

}  // namespace

nlohmann::ordered_json layout_json(const std::vector<SceneLight>& lights) {
  if (lights.size() > kMaxLights) {  // light slots (docs/server.md): the fields are the slots the lights share
    const LightSlots slots = LightSlots::assign(lights);
    bool soft[kMaxLights] = {};
    for (uint32_t f = 0; f < slots.slot_count(); ++f) soft[f] = slots.soft_slots()[f];
    const VisibilityLayout layout = VisibilityLayout::for_lights(std::span<const bool>(soft, slots.slot_count()));
    nlohmann::ordered_json dropped = nlohmann::ordered_json::array();
    for (const uint32_t i : slots.dropped()) dropped.push_back(light_name(lights, i));
    return {{"bits", layout.total_bits()},
            {"mask_bits", static_cast<uint32_t>(layout.mask_width())},
            {"light_slots", slots.slot_count()},
            {"light_slots_describe", slots.describe()},
            {"lights_without_slot", dropped}};
  }
  const VisibilityLayout layout = soft_layout(lights);
  nlohmann::ordered_json soft = nlohmann::ordered_json::array();
  for (uint32_t i = 0; i < layout.light_count; ++i) {
    if (layout.is_soft(i))
      soft.push_back({{"name", light_name(lights, i)}, {"first_bit", layout.offset[i]}, {"bits", layout.bits[i]}});
  }
  return {{"bits", layout.total_bits()},
          {"mask_bits", static_cast<uint32_t>(layout.mask_width())},
          {"soft_lights", soft},
          {"demoted", demoted_lights(lights)}};
}

std::string layout_line(const std::vector<SceneLight>& lights) {
  const VisibilityLayout layout = soft_layout(lights);
  if (!layout.any_soft()) return "no light with an extent: one bit per light";
  std::string out = "soft levels for clients that offer them:";
  const char* sep = " ";
  for (uint32_t i = 0; i < layout.light_count; ++i) {
    if (!layout.is_soft(i)) continue;
    out += sep + ("'" + light_name(lights, i) + "' bits ") + std::to_string(layout.offset[i]) + "-" +
           std::to_string(layout.offset[i] + layout.bits[i] - 1);
    sep = ", ";
  }
  return out + "; " + std::to_string(layout.total_bits()) + " bits per mask (" +
         std::to_string(static_cast<uint32_t>(layout.mask_width())) + "-bit masks)";
}

std::vector<std::string> demoted_lights(const std::vector<SceneLight>& lights) {
  const VisibilityLayout layout = soft_layout(lights);
  std::vector<std::string> out;
  for (uint32_t i = 0; i < layout.light_count; ++i)
    if (lights[i].has_extent() && !layout.is_soft(i)) out.push_back(light_name(lights, i));
  return out;
}

}  // namespace dhr::server::cli
