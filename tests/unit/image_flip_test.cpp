// LDR-FLIP (bench/metrics/include/metrics/image_flip.hpp) against values computed independently from the published formulas
// (image_flip_reference.hpp: a closed form for uniform images, a direct non-separable implementation).
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
#include <vector>

#include "metrics/image_flip.hpp"
#include "image_flip_reference.hpp"

namespace dhr {
namespace {

using namespace flip_reference;

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
