// LDR-FLIP (shared/core/image_flip.hpp) against values computed here from the published formulas:
//  - a closed form for uniform images (filters normalised, no features: the error is the remapped HyAB
//    distance of the two colours), computed step by step with the reference implementation's published
//    constants (its 9-digit D65 white and XYZ->RGB matrix), not with the production code's derived ones;
//  - a direct, non-separable implementation written here: full 2-D kernels built as the paper defines them
//    (the feature kernels normalised sign-wise in 2-D), clamp-to-edge 2-D correlation.
// Plus argument checks, the symmetries the metric has (argument order, mirroring, transposition) and one it
// lacks (colour channels are not interchangeable), monotonicity, locality, range and determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include "core/image_flip.hpp"

namespace dhr {
namespace {

using Rgb8 = std::array<uint8_t, 3>;
using Vec3 = std::array<double, 3>;

std::vector<uint8_t> uniform_image(uint32_t w, uint32_t h, Rgb8 c) {
  std::vector<uint8_t> img(static_cast<size_t>(w) * h * 4);
  for (size_t i = 0; i < img.size(); i += 4) {
    img[i] = c[0];
    img[i + 1] = c[1];
    img[i + 2] = c[2];
    img[i + 3] = 255;
  }
  return img;
}

// Deterministic pseudo-random bytes (a 64-bit LCG, top byte).
struct Lcg {
  uint64_t state;
  uint8_t next() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint8_t>(state >> 56);
  }
};

std::vector<uint8_t> random_image(uint32_t w, uint32_t h, uint64_t seed) {
  std::vector<uint8_t> img(static_cast<size_t>(w) * h * 4);
  Lcg rng{seed};
  for (uint8_t& b : img) b = rng.next();
  return img;
}

void set_pixel(std::vector<uint8_t>& img, uint32_t w, uint32_t x, uint32_t y, Rgb8 c) {
  const size_t i = (static_cast<size_t>(y) * w + x) * 4;
  img[i] = c[0];
  img[i + 1] = c[1];
  img[i + 2] = c[2];
}

// ------------------------------------------------ the published formulas, written out independently ---

// D65 white and XYZ->linear-RGB matrix as printed (9 digits) in NVlabs' reference implementation.
constexpr Vec3 kWhite{0.950428545, 1.0, 1.088900371};
constexpr std::array<Vec3, 3> kRgbToXyz{{{10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
                                         {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
                                         {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}}};
constexpr std::array<Vec3, 3> kXyzToRgb{{{3.241003275, -1.537398934, -0.498615861},
                                         {-0.969224334, 1.875930071, 0.041554224},
                                         {0.055639423, -0.204011202, 1.057148933}}};

Vec3 mat_mul(const std::array<Vec3, 3>& m, const Vec3& v) {
  Vec3 out{};
  for (int r = 0; r < 3; ++r) out[r] = m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2];
  return out;
}

double decode_srgb(uint8_t byte) {
  const double c = byte / 255.0;
  return c > 0.04045 ? std::pow((c + 0.055) / 1.055, 2.4) : c / 12.92;
}

Vec3 linear_rgb(Rgb8 c) { return {decode_srgb(c[0]), decode_srgb(c[1]), decode_srgb(c[2])}; }

// Linear RGB -> XYZ -> CIELAB -> Hunt-adjusted (a, b scaled by L / 100).
Vec3 hunt_lab(const Vec3& rgb) {
  const Vec3 xyz = mat_mul(kRgbToXyz, rgb);
  Vec3 f{};
  for (int i = 0; i < 3; ++i) {
    const double t = xyz[i] / kWhite[i];
    const double d = 6.0 / 29.0;
    f[i] = t > d * d * d ? std::pow(t, 1.0 / 3.0) : t / (3.0 * d * d) + 4.0 / 29.0;
  }
  const double l = 116.0 * f[1] - 16.0, a = 500.0 * (f[0] - f[1]), b = 200.0 * (f[1] - f[2]);
  return {l, l / 100.0 * a, l / 100.0 * b};
}

double hyab_distance(const Vec3& p, const Vec3& q) {
  return std::fabs(p[0] - q[0]) + std::sqrt((p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
}

// Colour error in [0,1]: HyAB^0.7, remapped with p_c = 0.4, p_t = 0.95 against c_max (green vs blue).
double colour_error_from_hyab(double distance) {
  const double qc = 0.7, pc = 0.4, pt = 0.95;
  const double cmax = std::pow(hyab_distance(hunt_lab({0, 1, 0}), hunt_lab({0, 0, 1})), qc);
  const double e = std::pow(distance, qc);
  return e < pc * cmax ? e * pt / (pc * cmax) : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0 - pt);
}

double uniform_closed_form(Rgb8 ref, Rgb8 test) {
  return colour_error_from_hyab(hyab_distance(hunt_lab(linear_rgb(ref)), hunt_lab(linear_rgb(test))));
}

// ------------------------------------------------------- direct (non-separable) FLIP, from the paper ---

struct Grid {
  int w = 0, h = 0;
  std::vector<double> v;
  double at(int x, int y) const { return v[static_cast<size_t>(y) * w + x]; }
  double& at(int x, int y) { return v[static_cast<size_t>(y) * w + x]; }
};

struct Kernel2d {
  int r = 0;
  std::vector<double> k;  // (2r+1)^2, k[(j + r) * (2r+1) + (i + r)] at offset (i, j)
  double at(int i, int j) const { return k[static_cast<size_t>((j + r) * (2 * r + 1) + (i + r))]; }
};

Grid correlate_clamped(const Grid& in, const Kernel2d& k) {
  Grid out{in.w, in.h, std::vector<double>(in.v.size())};
  for (int y = 0; y < in.h; ++y) {
    for (int x = 0; x < in.w; ++x) {
      double s = 0.0;
      for (int j = -k.r; j <= k.r; ++j) {
        for (int i = -k.r; i <= k.r; ++i) {
          s += k.at(i, j) * in.at(std::clamp(x + i, 0, in.w - 1), std::clamp(y + j, 0, in.h - 1));
        }
      }
      out.at(x, y) = s;
    }
  }
  return out;
}

Kernel2d csf_kernel(double ppd, double a1, double b1, double a2, double b2) {
  const double pi = std::numbers::pi;
  Kernel2d k;
  k.r = static_cast<int>(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * pi * pi)) * ppd));
  double sum = 0.0;
  for (int j = -k.r; j <= k.r; ++j) {
    for (int i = -k.r; i <= k.r; ++i) {
      const double z = (i / ppd) * (i / ppd) + (j / ppd) * (j / ppd);
      const double s = a1 * std::sqrt(pi / b1) * std::exp(-pi * pi * z / b1) +
                       a2 * std::sqrt(pi / b2) * std::exp(-pi * pi * z / b2);
      k.k.push_back(s);
      sum += s;
    }
  }
  for (double& v : k.k) v /= sum;
  return k;
}

// x-direction feature kernel (first or second derivative of a 2-D Gaussian), positive taps summing to 1 and
// negative ones to -1; `transpose` gives the y-direction one.
Kernel2d feature_kernel(double ppd, bool second_derivative, bool transpose) {
  const double sd = 0.5 * 0.082 * ppd;
  Kernel2d k;
  k.r = static_cast<int>(std::ceil(3.0 * sd));
  double pos = 0.0, neg = 0.0;
  for (int j = -k.r; j <= k.r; ++j) {
    for (int i = -k.r; i <= k.r; ++i) {
      const double x = transpose ? j : i, y = transpose ? i : j;
      const double g = std::exp(-(x * x + y * y) / (2.0 * sd * sd));
      const double v = second_derivative ? (x * x / (sd * sd) - 1.0) * g : -x * g;
      k.k.push_back(v);
      (v > 0 ? pos : neg) += v;
    }
  }
  for (double& v : k.k) v = v > 0 ? v / pos : v / -neg;
  return k;
}

struct DirectFlip {
  Grid colour, feature, error;
};

DirectFlip direct_flip(const std::vector<uint8_t>& ref, const std::vector<uint8_t>& test, int w, int h, double ppd) {
  const Kernel2d csf[3] = {csf_kernel(ppd, 1.0, 0.0047, 0.0, 1e-5), csf_kernel(ppd, 1.0, 0.0053, 0.0, 1e-5),
                           csf_kernel(ppd, 34.1, 0.04, 13.5, 0.025)};
  const Kernel2d features[4] = {feature_kernel(ppd, false, false), feature_kernel(ppd, false, true),
                                feature_kernel(ppd, true, false), feature_kernel(ppd, true, true)};
  const size_t n = static_cast<size_t>(w) * h;
  std::vector<Vec3> lab[2];
  Grid edge[2], point[2];
  for (int img = 0; img < 2; ++img) {
    const std::vector<uint8_t>& src = img == 0 ? ref : test;
    Grid opp[3];
    for (Grid& g : opp) g = Grid{w, h, std::vector<double>(n)};
    for (size_t p = 0; p < n; ++p) {
      const Vec3 xyz = mat_mul(kRgbToXyz, linear_rgb({src[4 * p], src[4 * p + 1], src[4 * p + 2]}));
      opp[0].v[p] = 116.0 * xyz[1] / kWhite[1] - 16.0;
      opp[1].v[p] = 500.0 * (xyz[0] / kWhite[0] - xyz[1] / kWhite[1]);
      opp[2].v[p] = 200.0 * (xyz[1] / kWhite[1] - xyz[2] / kWhite[2]);
    }
    Grid filtered[3];
    for (int c = 0; c < 3; ++c) filtered[c] = correlate_clamped(opp[c], csf[c]);
    for (size_t p = 0; p < n; ++p) {
      const double y = (filtered[0].v[p] + 16.0) / 116.0;
      const Vec3 xyz{(y + filtered[1].v[p] / 500.0) * kWhite[0], y * kWhite[1],
                     (y - filtered[2].v[p] / 200.0) * kWhite[2]};
      Vec3 rgb = mat_mul(kXyzToRgb, xyz);
      for (double& v : rgb) v = std::clamp(v, 0.0, 1.0);
      lab[img].push_back(hunt_lab(rgb));
    }
    Grid achromatic{w, h, std::vector<double>(n)};
    for (size_t p = 0; p < n; ++p) achromatic.v[p] = (opp[0].v[p] + 16.0) / 116.0;
    Grid resp[4];
    for (int f = 0; f < 4; ++f) resp[f] = correlate_clamped(achromatic, features[f]);
    edge[img] = point[img] = Grid{w, h, std::vector<double>(n)};
    for (size_t p = 0; p < n; ++p) {
      edge[img].v[p] = std::sqrt(resp[0].v[p] * resp[0].v[p] + resp[1].v[p] * resp[1].v[p]);
      point[img].v[p] = std::sqrt(resp[2].v[p] * resp[2].v[p] + resp[3].v[p] * resp[3].v[p]);
    }
  }
  DirectFlip out;
  out.colour = out.feature = out.error = Grid{w, h, std::vector<double>(n)};
  for (size_t p = 0; p < n; ++p) {
    out.colour.v[p] = colour_error_from_hyab(hyab_distance(lab[0][p], lab[1][p]));
    const double diff = std::max(std::fabs(edge[0].v[p] - edge[1].v[p]), std::fabs(point[0].v[p] - point[1].v[p]));
    out.feature.v[p] = std::sqrt(diff / std::sqrt(2.0));
    out.error.v[p] = std::pow(out.colour.v[p], 1.0 - out.feature.v[p]);
  }
  return out;
}

double max_abs_difference(const FlipResult& got, const Grid& expected) {
  double worst = 0.0;
  for (size_t i = 0; i < got.error_map.size(); ++i) {
    worst = std::max(worst, std::fabs(static_cast<double>(got.error_map[i]) - expected.v[i]));
  }
  return worst;
}

// --------------------------------------------------------------------------------------------- tests ---

TEST(ImageFlip, IdenticalImagesGiveExactlyZero) {
  const auto img = random_image(37, 23, 7);
  const auto r = flip_ldr(img, img, 37, 23);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->width, 37u);
  EXPECT_EQ(r->height, 23u);
  ASSERT_EQ(r->error_map.size(), 37u * 23u);
  EXPECT_EQ(r->mean, 0.0);
  for (float e : r->error_map) EXPECT_EQ(e, 0.0f);
}

TEST(ImageFlip, RejectsBadArguments) {
  const auto a = uniform_image(8, 6, {10, 20, 30});
  const auto b = uniform_image(8, 6, {40, 50, 60});
  const auto small = uniform_image(8, 5, {40, 50, 60});
  EXPECT_FALSE(flip_ldr(a, small, 8, 6).has_value());  // size mismatch
  EXPECT_FALSE(flip_ldr(small, a, 8, 6).has_value());
  EXPECT_FALSE(flip_ldr(a, b, 8, 5).has_value());  // spans of the wrong length
  EXPECT_FALSE(flip_ldr(a, b, 6, 10).has_value());
  EXPECT_FALSE(flip_ldr({}, {}, 0, 0).has_value());  // zero size
  EXPECT_FALSE(flip_ldr({}, {}, 0, 6).has_value());
  EXPECT_FALSE(flip_ldr({}, {}, 8, 0).has_value());
  for (double ppd : {0.0, -67.0, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::quiet_NaN(), 2.0 * kFlipMaxPixelsPerDegree}) {
    EXPECT_FALSE(flip_ldr(a, b, 8, 6, FlipParams{ppd}).has_value()) << ppd;
  }
  EXPECT_TRUE(flip_ldr(a, b, 8, 6).has_value());
  EXPECT_TRUE(flip_ldr(a, b, 1, 48).has_value());  // any shape with the right byte count
}

TEST(ImageFlip, UniformPairsMatchTheClosedForm) {
  const std::vector<std::array<Rgb8, 2>> pairs = {
      {{{0, 0, 0}, {255, 255, 255}}},   {{{128, 128, 128}, {129, 129, 129}}}, {{{128, 128, 128}, {140, 140, 140}}},
      {{{255, 0, 0}, {0, 255, 0}}},     {{{0, 255, 0}, {0, 0, 255}}},         {{{200, 60, 30}, {190, 70, 40}}},
      {{{12, 34, 250}, {13, 34, 251}}}, {{{255, 255, 0}, {0, 0, 0}}},         {{{90, 180, 120}, {30, 30, 30}}}};
  for (const auto& [ref, test] : pairs) {
    const double expected = uniform_closed_form(ref, test);
    for (double ppd : {67.0, 30.0, 9.5}) {
      const auto r = flip_ldr(uniform_image(24, 17, ref), uniform_image(24, 17, test), 24, 17, FlipParams{ppd});
      ASSERT_TRUE(r.has_value());
      EXPECT_NEAR(r->mean, expected, 1e-6) << +ref[0] << "," << +ref[1] << "," << +ref[2] << " ppd " << ppd;
      for (float e : r->error_map) ASSERT_NEAR(static_cast<double>(e), expected, 1e-6);
    }
  }
  // A hand-checkable anchor: black vs white is HyAB = |dL| = 100 (grey has a = b = 0), i.e. 100^0.7 against
  // c_max = 203.30^0.7, above the knee p_c * c_max, so 0.95 + 0.05 * (100^0.7 - 0.4 c) / (0.6 c) = 0.9673.
  EXPECT_NEAR(uniform_closed_form({0, 0, 0}, {255, 255, 255}), 0.9673, 1e-4);
}

TEST(ImageFlip, ErrorGrowsWithUniformColourDifference) {
  // Along the grey axis, either way from mid grey.
  for (int sign : {1, -1}) {
    double previous = -1.0;
    for (int d = 0; d <= 127; ++d) {
      const auto g = static_cast<uint8_t>(128 + sign * d);
      const auto r = flip_ldr(uniform_image(8, 8, {128, 128, 128}), uniform_image(8, 8, {g, g, g}), 8, 8);
      ASSERT_TRUE(r.has_value());
      EXPECT_GE(r->mean, previous) << "d " << d;
      previous = r->mean;
    }
  }
  // Random uniform colour pairs: ordered by their HyAB distance, the error never decreases.
  Lcg rng{99};
  std::vector<std::pair<double, double>> by_distance;
  for (int i = 0; i < 200; ++i) {
    const Rgb8 a{rng.next(), rng.next(), rng.next()}, b{rng.next(), rng.next(), rng.next()};
    const auto r = flip_ldr(uniform_image(4, 4, a), uniform_image(4, 4, b), 4, 4);
    ASSERT_TRUE(r.has_value());
    by_distance.emplace_back(hyab_distance(hunt_lab(linear_rgb(a)), hunt_lab(linear_rgb(b))), r->mean);
  }
  std::sort(by_distance.begin(), by_distance.end());
  for (size_t i = 1; i < by_distance.size(); ++i) EXPECT_GE(by_distance[i].second, by_distance[i - 1].second - 1e-9);
}

TEST(ImageFlip, MatchesDirectTwoDimensionalImplementation) {
  const int w = 29, h = 21;
  const std::vector<std::pair<uint64_t, double>> cases = {{1, 67.0}, {2, 67.0}, {3, 30.0}, {4, 5.0}, {5, 120.0}};
  for (const auto& [seed, ppd] : cases) {
    const auto ref = random_image(w, h, seed);
    auto test = ref;
    Lcg rng{seed + 1000};
    // Perturb a third of the bytes by up to +-24, so colour and feature errors both vary.
    for (uint8_t& b : test) {
      if (rng.next() < 85) b = static_cast<uint8_t>(std::clamp(b + rng.next() / 5 - 25, 0, 255));
    }
    const auto r = flip_ldr(ref, test, w, h, FlipParams{ppd});
    ASSERT_TRUE(r.has_value());
    const DirectFlip d = direct_flip(ref, test, w, h, ppd);
    EXPECT_LT(max_abs_difference(*r, d.error), 1e-6) << "seed " << seed << " ppd " << ppd;
  }
}

TEST(ImageFlip, SingleChangedPixelIsLocal) {
  const int n = 41, c = 20;
  const auto ref = uniform_image(n, n, {128, 128, 128});
  auto test = ref;
  set_pixel(test, n, c, c, {255, 255, 255});
  const auto r = flip_ldr(ref, test, n, n);
  ASSERT_TRUE(r.has_value());
  const DirectFlip d = direct_flip(ref, test, n, n, 67.0);
  EXPECT_LT(max_abs_difference(*r, d.error), 1e-6);
  // At 67 ppd the CSF kernels reach 10 px and the feature kernels 9 px (Chebyshev, square kernels).
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const int dist = std::max(std::abs(x - c), std::abs(y - c));
      const float e = r->error_map[static_cast<size_t>(y) * n + x];
      if (dist > 10) {
        EXPECT_EQ(e, 0.0f) << x << "," << y;
      }
      if (dist > 9) {
        EXPECT_EQ(d.feature.at(x, y), 0.0) << x << "," << y;
      }
    }
  }
  EXPECT_GT(d.feature.at(c, c), 0.0);
  // The feature term raises the error above the colour-only error where it acts.
  EXPECT_GT(static_cast<double>(r->error_map[static_cast<size_t>(c) * n + c]), d.colour.at(c, c) + 1e-3);
}

TEST(ImageFlip, EdgeShiftRaisesFeatureErrorNearTheEdge) {
  const int w = 48, h = 16, edge = 24;
  auto ref = uniform_image(w, h, {20, 20, 20});
  auto test = ref;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (x >= edge) set_pixel(ref, w, x, y, {230, 230, 230});
      if (x >= edge + 1) set_pixel(test, w, x, y, {230, 230, 230});
    }
  }
  const auto r = flip_ldr(ref, test, w, h);
  ASSERT_TRUE(r.has_value());
  const DirectFlip d = direct_flip(ref, test, w, h, 67.0);
  EXPECT_LT(max_abs_difference(*r, d.error), 1e-6);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      // The changed column is x = edge; kernels reach 10 (colour) and 9 (features) px.
      if (std::abs(x - edge) > 10) {
        EXPECT_EQ(r->error_map[static_cast<size_t>(y) * w + x], 0.0f) << x;
      }
      if (std::abs(x - edge) > 9) {
        EXPECT_EQ(d.feature.at(x, y), 0.0) << x;
      }
    }
    // The changed column lies midway between the two edges, where both images' edge and point responses are
    // equal by symmetry; the feature difference peaks beside it.
    int peak = edge;
    for (int x = edge - 9; x <= edge + 9; ++x) {
      if (d.feature.at(x, y) > d.feature.at(peak, y)) peak = x;
    }
    EXPECT_GT(d.feature.at(peak, y), 0.1);
    EXPECT_GT(static_cast<double>(r->error_map[static_cast<size_t>(y) * w + peak]), d.colour.at(peak, y) + 1e-3);
  }
}

TEST(ImageFlip, ErrorMapIsInUnitRangeForRandomImages) {
  for (uint64_t seed = 10; seed < 16; ++seed) {
    const auto a = random_image(53, 31, seed), b = random_image(53, 31, seed + 100);
    const auto r = flip_ldr(a, b, 53, 31, FlipParams{seed % 2 ? 67.0 : 12.0});
    ASSERT_TRUE(r.has_value());
    double sum = 0.0;
    for (float e : r->error_map) {
      ASSERT_GE(e, 0.0f);
      ASSERT_LE(e, 1.0f);
      sum += static_cast<double>(e);
    }
    EXPECT_DOUBLE_EQ(r->mean, sum / static_cast<double>(r->error_map.size()));
    EXPECT_GT(r->mean, 0.0);
  }
  // Extreme inputs: black vs white noise.
  std::vector<uint8_t> a(32 * 32 * 4), b(32 * 32 * 4);
  Lcg rng{5};
  for (size_t i = 0; i < a.size(); ++i) {
    a[i] = rng.next() < 128 ? 0 : 255;
    b[i] = static_cast<uint8_t>(255 - a[i]);
  }
  const auto r = flip_ldr(a, b, 32, 32);
  ASSERT_TRUE(r.has_value());
  for (float e : r->error_map) ASSERT_TRUE(e >= 0.0f && e <= 1.0f);
}

TEST(ImageFlip, ExtremeViewingConditionsStayFinite) {
  // Tiny ppd (kernel tails underflow) and large ppd (kernels far wider than the image, all clamped taps).
  const auto a = random_image(16, 12, 61), b = random_image(16, 12, 62);
  for (double ppd : {1e-3, 0.5, 1000.0, kFlipMaxPixelsPerDegree}) {
    const auto r = flip_ldr(a, b, 16, 12, FlipParams{ppd});
    ASSERT_TRUE(r.has_value()) << ppd;
    for (float e : r->error_map) ASSERT_TRUE(e >= 0.0f && e <= 1.0f) << ppd;
    EXPECT_TRUE(std::isfinite(r->mean));
  }
  const auto r = flip_ldr(a, b, 16, 12, FlipParams{1000.0});
  ASSERT_TRUE(r.has_value());
  EXPECT_LT(max_abs_difference(*r, direct_flip(a, b, 16, 12, 1000.0).error), 1e-6);
}

TEST(ImageFlip, IsSymmetricInItsArguments) {
  // Every step treats both images alike and the distances (HyAB, |edge - edge'|) are symmetric, so swapping
  // reference and test gives the same map bit for bit.
  const auto a = random_image(31, 19, 21), b = random_image(31, 19, 22);
  const auto ab = flip_ldr(a, b, 31, 19), ba = flip_ldr(b, a, 31, 19);
  ASSERT_TRUE(ab && ba);
  EXPECT_EQ(ab->error_map, ba->error_map);
  EXPECT_EQ(ab->mean, ba->mean);
}

TEST(ImageFlip, CommutesWithMirroringAndTransposition) {
  // Symmetric Gaussians, antisymmetric edge kernels (only their magnitude is used) and symmetric padding:
  // mirroring or transposing both inputs mirrors or transposes the map (up to summation order rounding).
  const uint32_t w = 27, h = 18;
  const auto a = random_image(w, h, 31), b = random_image(w, h, 32);
  auto mirror = [&](const std::vector<uint8_t>& img) {
    std::vector<uint8_t> out(img.size());
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        for (int c = 0; c < 4; ++c) out[(y * w + (w - 1 - x)) * 4 + c] = img[(y * w + x) * 4 + c];
    return out;
  };
  auto transpose = [&](const std::vector<uint8_t>& img) {
    std::vector<uint8_t> out(img.size());
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        for (int c = 0; c < 4; ++c) out[(x * h + y) * 4 + c] = img[(y * w + x) * 4 + c];
    return out;
  };
  const auto base = flip_ldr(a, b, w, h);
  const auto mirrored = flip_ldr(mirror(a), mirror(b), w, h);
  const auto transposed = flip_ldr(transpose(a), transpose(b), h, w);
  ASSERT_TRUE(base && mirrored && transposed);
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      const float e = base->error_map[y * w + x];
      EXPECT_NEAR(e, mirrored->error_map[y * w + (w - 1 - x)], 1e-6f);
      EXPECT_NEAR(e, transposed->error_map[x * h + y], 1e-6f);
    }
  }
}

TEST(ImageFlip, ColourChannelsAreNotInterchangeable) {
  // Not a symmetry the metric has: the opponent space and CIELAB weigh R, G and B differently, so the same
  // step on a different channel gives a different error.
  const auto black = uniform_image(8, 8, {0, 0, 0});
  const auto red = flip_ldr(black, uniform_image(8, 8, {128, 0, 0}), 8, 8);
  const auto green = flip_ldr(black, uniform_image(8, 8, {0, 128, 0}), 8, 8);
  const auto blue = flip_ldr(black, uniform_image(8, 8, {0, 0, 128}), 8, 8);
  ASSERT_TRUE(red && green && blue);
  EXPECT_GT(std::fabs(red->mean - green->mean), 1e-3);
  EXPECT_GT(std::fabs(green->mean - blue->mean), 1e-3);
  EXPECT_GT(std::fabs(red->mean - blue->mean), 1e-3);
}

TEST(ImageFlip, IsDeterministicAndIgnoresAlpha) {
  const auto a = random_image(40, 30, 41), b = random_image(40, 30, 42);
  auto a2 = a, b2 = b;
  for (size_t i = 3; i < a2.size(); i += 4) {
    a2[i] = 0;
    b2[i] = 77;
  }
  const auto r1 = flip_ldr(a, b, 40, 30), r2 = flip_ldr(a, b, 40, 30), r3 = flip_ldr(a2, b2, 40, 30);
  ASSERT_TRUE(r1 && r2 && r3);
  EXPECT_EQ(r1->error_map, r2->error_map);
  EXPECT_EQ(r1->error_map, r3->error_map);
}

// Timing only (never asserted): ./dhr_unit_tests --gtest_also_run_disabled_tests
// --gtest_filter=ImageFlip.DISABLED_MeasureSpeed prints one JSON line per size.
TEST(ImageFlip, DISABLED_MeasureSpeed) {
  for (const auto& [w, h, reps] : std::vector<std::array<uint32_t, 3>>{{160, 120, 20}, {320, 240, 10}, {1280, 720, 3}}) {
    const auto a = random_image(w, h, 1), b = random_image(w, h, 2);
    double best = std::numeric_limits<double>::infinity(), total = 0.0;
    double mean = 0.0;
    for (uint32_t i = 0; i < reps; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      const auto r = flip_ldr(a, b, w, h);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      ASSERT_TRUE(r.has_value());
      mean = r->mean;
      best = std::min(best, ms);
      total += ms;
    }
    std::printf("{\"bench\":\"flip_ldr\",\"width\":%u,\"height\":%u,\"ppd\":67,\"reps\":%u,\"best_ms\":%.3f,"
                "\"mean_ms\":%.3f,\"flip_mean\":%.6f}\n",
                w, h, reps, best, total / reps, mean);
  }
}

}  // namespace
}  // namespace dhr
