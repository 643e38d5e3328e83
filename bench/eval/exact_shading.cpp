#include "exact_shading.hpp"

#include "shaders/display_encode.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace dhr::eval {
namespace {

// The inverse of display_encode::tonemap_aces on [0, 1): the root of (2.51 - 2.43 y) v^2 + (0.03 - 0.59 y) v - 0.14 y.
float inverse_aces(float display) {
  const double y = static_cast<double>(display);
  const double a = 2.51 - 2.43 * y, b = 0.03 - 0.59 * y, c = -0.14 * y;
  return static_cast<float>((-b + std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a));
}

float srgb_decode(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

const std::array<float, 256>& radiance_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int b = 0; b < 256; ++b) t[static_cast<size_t>(b)] = inverse_aces(srgb_decode(static_cast<float>(b) / 255.0f));
    return t;
  }();
  return table;
}

uint8_t encode_byte(float radiance) {
  const float v = display_encode::srgb_encode(display_encode::tonemap_aces(radiance));
  return static_cast<uint8_t>(std::clamp(std::lround(v * 255.0f), 0L, 255L));
}

}  // namespace

float exposed_radiance(uint8_t byte) { return radiance_table()[byte]; }

RadianceSum::RadianceSum(const std::vector<uint8_t>& base)
    : base_(base), radiance_(base.size() / 4 * 3), stepped_(base.size() / 4, 0) {
  for (size_t p = 0; p < base.size() / 4; ++p)
    for (size_t c = 0; c < 3; ++c) radiance_[p * 3 + c] = exposed_radiance(base[p * 4 + c]);
}

void RadianceSum::add_step(const std::vector<uint8_t>& stepped, std::span<const float> weight) {
  if (stepped.size() != base_.size() || weight.size() != base_.size() / 4)
    throw std::invalid_argument("RadianceSum: pictures of different sizes");
  for (size_t p = 0; p < weight.size(); ++p) {
    if (weight[p] == 0.0f) continue;
    stepped_[p] = 1;
    for (size_t c = 0; c < 3; ++c)
      radiance_[p * 3 + c] += weight[p] * (exposed_radiance(stepped[p * 4 + c]) - exposed_radiance(base_[p * 4 + c]));
  }
}

std::vector<uint8_t> RadianceSum::encode() const {
  std::vector<uint8_t> out = base_;
  for (size_t p = 0; p < out.size() / 4; ++p) {
    if (!stepped_[p]) continue;  // the base's bytes as they are
    for (size_t c = 0; c < 3; ++c) out[p * 4 + c] = encode_byte(radiance_[p * 3 + c]);
  }
  return out;
}

}  // namespace dhr::eval
