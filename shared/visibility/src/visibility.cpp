#include "visibility/visibility.hpp"

#include <stdexcept>
#include <string>

namespace dhr {

std::optional<MaskWidth> mask_width_from_bits(uint32_t bits) {
  switch (bits) {
    case 8: return MaskWidth::k8;
    case 16: return MaskWidth::k16;
    case 32: return MaskWidth::k32;
    default: return std::nullopt;
  }
}

VisibilityBuffer VisibilityBuffer::create(uint32_t width, uint32_t height, uint32_t light_count) {
  if (light_count > kMaxLights)
    throw std::invalid_argument("visibility buffer: " + std::to_string(light_count) + " lights (max " +
                                std::to_string(kMaxLights) + ")");
  if (width > kMaxBufferDimension || height > kMaxBufferDimension)
    throw std::invalid_argument("visibility buffer: " + std::to_string(width) + "x" + std::to_string(height) +
                                " exceeds " + std::to_string(kMaxBufferDimension));
  VisibilityBuffer b;
  b.width = width;
  b.height = height;
  b.light_count = light_count;
  b.mask_bits = mask_width_for_light_count(light_count);
  b.data.assign(b.size_bytes(), 0);
  return b;
}

VisibilityBuffer VisibilityBuffer::with_mask_width(MaskWidth to) const {
  if (mask_bytes(to) < 4 && light_count > static_cast<uint32_t>(to)) {
    throw std::invalid_argument("visibility buffer: " + std::to_string(light_count) + " lights do not fit " +
                                std::to_string(static_cast<uint32_t>(to)) + "-bit masks");
  }
  VisibilityBuffer out = *this;
  out.mask_bits = to;
  out.data.assign(pixel_count() * mask_bytes(to), 0);
  for (size_t i = 0; i < pixel_count(); ++i) out.set_mask_at(i, mask_at(i));
  return out;
}

}  // namespace dhr
