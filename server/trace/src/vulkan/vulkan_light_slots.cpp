// The light slots (scene/light_slots.hpp) as the ray-generation shader reads them (kVisBindingLightSlots): the
// grid's origin moved into the scene-relative frame (in double, then rounded to float like every position there),
// its cell edge, its cells per axis and fields per row, then the table, one uint per entry.
#include "trace/vulkan/vulkan_tracer_internal.hpp"

#include <bit>

namespace dhr::server::detail {

std::vector<uint32_t> light_slot_words(const LightSlots& slots, const glm::dvec3& origin) {
  std::vector<uint32_t> out(shader::kVisSlotHeaderWords, 0u);
  if (slots.is_identity()) return out;  // never read: the shader is told kVisLightSlots only with a grid
  for (int a = 0; a < 3; ++a)
    out[a] = std::bit_cast<uint32_t>(static_cast<float>(static_cast<double>(slots.origin_mm()[a]) - origin[a] * 1000.0));
  out[3] = std::bit_cast<uint32_t>(static_cast<float>(slots.cell_mm()));
  for (int a = 0; a < 3; ++a) out[4 + a] = slots.cells()[a];
  out[7] = slots.slot_count();
  out.reserve(out.size() + slots.table().size());
  for (uint16_t light : slots.table()) out.push_back(light == kNoSlotLight ? shader::kVisNoSlotLight : light);
  return out;
}

}  // namespace dhr::server::detail
