// Image metrics (bench/metrics/include/metrics/image_metrics.hpp): PSNR and SSIM against hand-computed and analytic values
// and against a direct (non-separable, two-pass) double-precision SSIM written here; the bitwise
// visibility error on hand-made buffers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "metrics/image_metrics.hpp"

namespace dhr {
namespace {

LumaImage make_image(uint32_t w, uint32_t h, double value) {
  LumaImage img;
  img.width = w;
  img.height = h;
  img.pixels.assign(img.pixel_count(), value);
  return img;
}

// Deterministic pseudo-random luma in [0, 255] (a 64-bit LCG; no <random> distributions).
LumaImage random_image(uint32_t w, uint32_t h, uint64_t seed) {
  LumaImage img = make_image(w, h, 0.0);
  uint64_t state = seed * 6364136223846793005ull + 1442695040888963407ull;
  for (double& v : img.pixels) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    v = static_cast<double>(state >> 56);
  }
  return img;
}

// SSIM the slow, obvious way: a 2-D Gaussian weight table built directly, and for every valid window the
// weighted mean, then variances and covariance as weighted sums of centred products (two passes).
double direct_ssim(const LumaImage& a, const LumaImage& b) {
  const int k = 11, r = 5;
  const double sigma = 1.5, c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
  std::vector<double> weight(k * k);
  double total = 0.0;
  for (int j = 0; j < k; ++j) {
    for (int i = 0; i < k; ++i) {
      weight[j * k + i] = std::exp(-((i - r) * (i - r) + (j - r) * (j - r)) / (2.0 * sigma * sigma));
      total += weight[j * k + i];
    }
  }
  for (double& v : weight) v /= total;
  const int w = static_cast<int>(a.width), h = static_cast<int>(a.height);
  double sum = 0.0;
  int count = 0;
  for (int y0 = 0; y0 + k <= h; ++y0) {
    for (int x0 = 0; x0 + k <= w; ++x0) {
      double ma = 0.0, mb = 0.0;
      for (int j = 0; j < k; ++j) {
        for (int i = 0; i < k; ++i) {
          ma += weight[j * k + i] * a.pixels[(y0 + j) * w + x0 + i];
          mb += weight[j * k + i] * b.pixels[(y0 + j) * w + x0 + i];
        }
      }
      double va = 0.0, vb = 0.0, cov = 0.0;
      for (int j = 0; j < k; ++j) {
        for (int i = 0; i < k; ++i) {
          const double da = a.pixels[(y0 + j) * w + x0 + i] - ma, db = b.pixels[(y0 + j) * w + x0 + i] - mb;
          va += weight[j * k + i] * da * da;
          vb += weight[j * k + i] * db * db;
          cov += weight[j * k + i] * da * db;
        }
      }
      sum += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
      ++count;
    }
  }
  return sum / count;
}

TEST(ImageMetricsTest, IdenticalImagesGiveSsimOneAndInfinitePsnr) {
  const LumaImage a = random_image(40, 30, 1);
  EXPECT_EQ(*ssim(a, a), 1.0);
  EXPECT_EQ(*psnr(a, a), std::numeric_limits<double>::infinity());
}

TEST(ImageMetricsTest, PsnrOfHandComputedCases) {
  // One of four pixels off by the full range: MSE = 255^2 / 4 -> PSNR = 10 log10(4).
  LumaImage a = make_image(2, 2, 0.0), b = make_image(2, 2, 0.0);
  b.pixels[0] = 255.0;
  EXPECT_NEAR(*psnr(a, b), 10.0 * std::log10(4.0), 1e-12);
  EXPECT_NEAR(*psnr(a, b), 6.0206, 1e-4);
  // A constant offset of 5: MSE = 25.
  const LumaImage c = random_image(20, 20, 2);
  LumaImage d = c;
  for (double& v : d.pixels) v += 5.0;
  EXPECT_NEAR(*psnr(c, d), 10.0 * std::log10(255.0 * 255.0 / 25.0), 1e-9);
  EXPECT_NEAR(*psnr(c, d, 1.0), 10.0 * std::log10(1.0 / 25.0), 1e-9);
}

TEST(ImageMetricsTest, SsimOfConstantImagesIsTheLuminanceTerm) {
  // No variance anywhere: the contrast-structure term is C2/C2 = 1, SSIM = (2ab + C1) / (a^2 + b^2 + C1).
  const double c1 = (0.01 * 255) * (0.01 * 255);
  const LumaImage a = make_image(16, 16, 100.0), b = make_image(16, 16, 120.0);
  EXPECT_NEAR(*ssim(a, b), (2 * 100.0 * 120.0 + c1) / (100.0 * 100.0 + 120.0 * 120.0 + c1), 1e-9);
  const LumaImage black = make_image(16, 16, 0.0), white = make_image(16, 16, 255.0);
  EXPECT_NEAR(*ssim(black, white), c1 / (255.0 * 255.0 + c1), 1e-9);
}

TEST(ImageMetricsTest, SsimOfInvertedCheckerboardMatchesTheClosedForm) {
  // a = m + d s, b = m - d s with s = (-1)^(x+y). Under the separable window every position sees the
  // same weighted mean of s up to sign, q = (sum_i g_i (-1)^i)^2, so mean_a = m + e, mean_b = m - e with
  // |e| = d q, var_a = var_b = d^2 (1 - q^2), cov = -var. SSIM is the same closed form everywhere.
  const double m = 128.0, d = 50.0;
  LumaImage a = make_image(24, 20, 0.0), b = a;
  for (uint32_t y = 0; y < a.height; ++y) {
    for (uint32_t x = 0; x < a.width; ++x) {
      const double s = (x + y) % 2 == 0 ? 1.0 : -1.0;
      a.pixels[y * a.width + x] = m + d * s;
      b.pixels[y * a.width + x] = m - d * s;
    }
  }
  const std::vector<double> g = ssim_gaussian_1d(11, 1.5);
  double alt = 0.0;
  for (size_t i = 0; i < g.size(); ++i) alt += (i % 2 == 0 ? 1.0 : -1.0) * g[i];
  const double q = alt * alt, e = d * q, var = d * d * (1.0 - q * q);
  const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
  const double expected = ((2 * (m + e) * (m - e) + c1) * (-2 * var + c2)) /
                          (((m + e) * (m + e) + (m - e) * (m - e) + c1) * (2 * var + c2));
  EXPECT_NEAR(*ssim(a, b), expected, 1e-9);
  EXPECT_LT(expected, -0.9);  // anti-correlated structure: SSIM near -1
}

TEST(ImageMetricsTest, SsimMatchesADirectWindowedImplementation) {
  const LumaImage a = random_image(37, 29, 3), b = random_image(37, 29, 4);
  LumaImage offset = a, scaled = a, smooth = a;
  for (double& v : offset.pixels) v = v + 10.0;
  for (double& v : scaled.pixels) v = 0.5 * v;
  for (size_t i = 1; i < smooth.pixels.size(); ++i) smooth.pixels[i] = 0.5 * (a.pixels[i] + a.pixels[i - 1]);
  for (const LumaImage* other : std::vector<const LumaImage*>{&b, &offset, &scaled, &smooth}) {
    const double expected = direct_ssim(a, *other);
    EXPECT_NEAR(*ssim(a, *other), expected, 1e-10);
    EXPECT_NEAR(*ssim(*other, a), expected, 1e-10);  // symmetric
  }
  EXPECT_LT(*ssim(a, b), 0.1);        // independent noise
  EXPECT_GT(*ssim(a, offset), 0.99);  // a small offset barely changes structure or luminance
}

TEST(ImageMetricsTest, GaussianWindowIsNormalisedAndSymmetric) {
  const std::vector<double> g = ssim_gaussian_1d(11, 1.5);
  ASSERT_EQ(g.size(), 11u);
  double sum = 0.0, raw = 0.0;
  for (size_t i = 0; i < g.size(); ++i) {
    sum += g[i];
    EXPECT_DOUBLE_EQ(g[i], g[10 - i]);
    raw += std::exp(-(static_cast<double>(i) - 5.0) * (static_cast<double>(i) - 5.0) / 4.5);
  }
  EXPECT_NEAR(sum, 1.0, 1e-15);
  EXPECT_NEAR(g[5], 1.0 / raw, 1e-15);
}

TEST(ImageMetricsTest, RejectsMismatchedOrTooSmallImages) {
  const LumaImage a = make_image(16, 16, 1.0), b = make_image(16, 15, 1.0), tiny = make_image(10, 10, 1.0);
  EXPECT_FALSE(ssim(a, b).has_value());
  EXPECT_FALSE(psnr(a, b).has_value());
  EXPECT_FALSE(ssim(tiny, tiny).has_value());
  EXPECT_TRUE(psnr(tiny, tiny).has_value());
  EXPECT_FALSE(psnr(LumaImage{}, LumaImage{}).has_value());
  SsimParams even;
  even.window = 10;
  EXPECT_FALSE(ssim(a, a, even).has_value());
  LumaImage broken = a;
  broken.pixels.pop_back();
  EXPECT_FALSE(ssim(broken, a).has_value());
}

TEST(ImageMetricsTest, LumaIsBt601OfTheEncodedValues) {
  const std::vector<uint8_t> rgba = {255, 255, 255, 0, 255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255};
  const LumaImage y = luma_from_rgba8(rgba, 2, 2);
  ASSERT_EQ(y.pixels.size(), 4u);
  EXPECT_NEAR(y.pixels[0], 255.0, 1e-9);
  EXPECT_NEAR(y.pixels[1], 0.299 * 255, 1e-9);
  EXPECT_NEAR(y.pixels[2], 0.587 * 255, 1e-9);
  EXPECT_NEAR(y.pixels[3], 0.114 * 255, 1e-9);
  EXPECT_TRUE(luma_from_rgba8(rgba, 3, 2).pixels.empty());
}

TEST(ImageMetricsTest, BitErrorCountsWrongBitsPerLight) {
  VisibilityBuffer a = VisibilityBuffer::create(2, 2, 3), b = VisibilityBuffer::create(2, 2, 3);
  a.set(0, 0, 0b111);
  b.set(0, 0, 0b101);  // light 1 wrong
  a.set(1, 0, 0b001);
  b.set(1, 0, 0b110);  // all three wrong
  a.set(0, 1, 0b100);
  b.set(0, 1, 0b100);  // equal
  b.set(1, 1, 0b001);  // light 0 wrong
  const std::optional<BitError> e = visibility_bit_error(a, b);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->pixels, 4u);
  EXPECT_EQ(e->wrong, (std::vector<uint64_t>{2, 2, 1}));
  EXPECT_EQ(e->wrong_bits(), 5u);
  EXPECT_DOUBLE_EQ(e->fraction(), 5.0 / 12.0);
  EXPECT_DOUBLE_EQ(e->light_fraction(0), 0.5);
  EXPECT_DOUBLE_EQ(e->light_fraction(2), 0.25);
  EXPECT_DOUBLE_EQ(visibility_bit_error(a, a)->fraction(), 0.0);
}

TEST(ImageMetricsTest, BitErrorIgnoresBitsAboveTheLightCountAndRejectsMismatches) {
  VisibilityBuffer a = VisibilityBuffer::create(3, 1, 2), b = VisibilityBuffer::create(3, 1, 2);
  b.set(0, 0, 0b1100);  // bits of lights that do not exist
  EXPECT_EQ(visibility_bit_error(a, b)->wrong_bits(), 0u);
  EXPECT_FALSE(visibility_bit_error(a, VisibilityBuffer::create(3, 1, 3)).has_value());
  EXPECT_FALSE(visibility_bit_error(a, VisibilityBuffer::create(1, 3, 2)).has_value());
  VisibilityBuffer broken = a;
  broken.data.pop_back();
  EXPECT_FALSE(visibility_bit_error(a, broken).has_value());
}

}  // namespace
}  // namespace dhr
