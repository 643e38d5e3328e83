#include "visibility_error.hpp"

#include "render/soft_refine.hpp"

#include <cmath>

namespace dhr::eval {

double VisibilityError::mean() const {
  double sum = 0.0;
  for (const double v : per_light) sum += v;
  const double n = static_cast<double>(surface_pixels) * static_cast<double>(per_light.size());
  return n > 0.0 ? sum / n : 0.0;
}

double VisibilityError::light_mean(uint32_t light) const {
  if (light >= per_light.size() || surface_pixels == 0) return 0.0;
  return per_light[light] / static_cast<double>(surface_pixels);
}

std::optional<VisibilityError> visibility_error(const VisibilityBuffer& shown, const VisibilityLayout& layout,
                                                const ExactVisibility& exact, std::span<const uint32_t> soft) {
  if (shown.width != exact.width || shown.height != exact.height || shown.light_count != layout.total_bits() ||
      exact.lights != layout.light_count || shown.data.size() != shown.size_bytes() ||
      (!soft.empty() && soft.size() != shown.pixel_count())) {
    return std::nullopt;
  }
  VisibilityError out;
  out.per_light.assign(layout.light_count, 0.0);
  for (size_t p = 0; p < shown.pixel_count(); ++p) {
    if (!exact.surface[p]) continue;
    ++out.surface_pixels;
    const uint32_t mask = shown.mask_at(p);
    for (uint32_t l = 0; l < layout.light_count; ++l) {
      const double k = soft.empty() ? static_cast<double>(layout.visibility(mask, l))
                                    : render::shaded_share(layout, mask, soft[p], l);
      out.per_light[l] += std::fabs(k - static_cast<double>(exact.fraction[p * exact.lights + l]));
    }
  }
  return out;
}

}  // namespace dhr::eval
