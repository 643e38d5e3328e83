// An independent LDR-FLIP for tests/unit/image_flip_test.cpp, written from the published formulas:
//  - uniform_closed_form: the error of two uniform images (filters normalised, no features: the remapped HyAB
//    distance of the two colours), with the reference implementation's published constants (its 9-digit D65
//    white and XYZ->RGB matrix), not the production code's derived ones;
//  - direct_flip: a direct, non-separable implementation: full 2-D kernels built as the paper defines them
//    (the feature kernels normalised sign-wise in 2-D), clamp-to-edge 2-D correlation.
// Slow on purpose (O(pixels x kernel area)); small images only.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "metrics/image_flip.hpp"

namespace dhr::flip_reference {

using Rgb8 = std::array<uint8_t, 3>;
using Vec3 = std::array<double, 3>;

Vec3 linear_rgb(Rgb8 c);             // sRGB bytes -> linear RGB
Vec3 hunt_lab(const Vec3& rgb);      // linear RGB -> Hunt-adjusted CIELAB
double hyab_distance(const Vec3& p, const Vec3& q);
double uniform_closed_form(Rgb8 ref, Rgb8 test);

struct Grid {
  int w = 0, h = 0;
  std::vector<double> v;
  double at(int x, int y) const { return v[static_cast<size_t>(y) * w + x]; }
  double& at(int x, int y) { return v[static_cast<size_t>(y) * w + x]; }
};

struct DirectFlip {
  Grid colour, feature, error;
};

// RGBA8 images (alpha ignored), reference first.
DirectFlip direct_flip(const std::vector<uint8_t>& ref, const std::vector<uint8_t>& test, int w, int h, double ppd);

double max_abs_difference(const FlipResult& got, const Grid& expected);

}  // namespace dhr::flip_reference
