// The truth's picture with fractional visibility, from pictures the client's pipeline shades with levels.
//
// The client shades a soft light with its level / 7 (client/shade.h): radiance = sum_i k_i * term_i is linear in
// each k_i. The truth renders once with every soft light at the level nearest its exact fraction k, and once per
// soft light with that light's level one step toward k; the exact radiance is the first picture's plus, per light,
// |7k - level| times the step's difference. The sums are taken in radiance (exposed, before the display encoding
// of shaders/display_encode.h, inverted per byte) and encoded back: exact up to the pictures' 8-bit rounding, and
// byte for byte the nearest-level picture wherever every k sits on a level (hard shadows, fully lit, umbrae).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace dhr::eval {

// The exposed radiance a display byte stands for (the inverse of the ACES curve and the sRGB encoding at the
// byte's value; 255 gives the curve's end).
float exposed_radiance(uint8_t byte);

class RadianceSum {
 public:
  // `base`: RGBA8 sRGB bytes, the picture with every soft light at its nearest level.
  explicit RadianceSum(const std::vector<uint8_t>& base);
  // Adds weight[p] x (stepped - base) at each pixel p (RGB; alpha is the base's). Sizes must match.
  void add_step(const std::vector<uint8_t>& stepped, std::span<const float> weight);
  // The sum, display-encoded again (RGBA8).
  std::vector<uint8_t> encode() const;

 private:
  const std::vector<uint8_t>& base_;
  std::vector<float> radiance_;  // RGB per pixel
  std::vector<uint8_t> stepped_;  // per pixel: a step was added (others keep the base's bytes)
};

}  // namespace dhr::eval
