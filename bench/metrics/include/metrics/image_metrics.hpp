// Image and visibility error metrics for the evaluation (dhr-eval) and tests.
//
// Images are single-channel luma planes (row-major doubles). luma_from_rgba8 takes display-encoded RGBA8
// bytes (what the client's shading pass writes) and returns Y' = 0.299 R' + 0.587 G' + 0.114 B' on the
// encoded values, in [0, 255] (BT.601 luma, as MATLAB's rgb2gray that SSIM is usually computed with).
//
// SSIM: Wang, Bovik, Sheikh, Simoncelli 2004, as their reference ssim_index.m: an 11x11 Gaussian window
// (sigma 1.5, normalised to sum 1), K1 = 0.01, K2 = 0.03, dynamic range L = 255 (luma in [0, 255]),
// local statistics over the "valid" window positions only (no padding, no downsampling), mean of the map.
// Computed with a separable filter in double precision.
//
// FLIP (Andersson et al. 2020, LDR-FLIP on RGBA8 colour images) is in metrics/image_flip.hpp.
#pragma once
#include "visibility/visibility.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace dhr {

struct LumaImage {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<double> pixels;  // width * height, row-major

  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
  bool consistent() const { return pixels.size() == pixel_count(); }
};

// BT.601 luma of RGBA8 pixels (alpha ignored). An empty image when rgba.size() != width * height * 4.
LumaImage luma_from_rgba8(std::span<const uint8_t> rgba, uint32_t width, uint32_t height);

// PSNR in dB with the given peak value: 10 log10(peak^2 / MSE); +infinity for identical images.
// std::nullopt for images of different or zero size.
std::optional<double> psnr(const LumaImage& a, const LumaImage& b, double peak = 255.0);

struct SsimParams {
  uint32_t window = 11;  // odd
  double sigma = 1.5;
  double k1 = 0.01;
  double k2 = 0.03;
  double dynamic_range = 255.0;  // L
};

// Mean SSIM over the valid window positions. std::nullopt for images of different size, smaller than the
// window, or bad parameters (even or zero window, non-positive sigma or range).
std::optional<double> ssim(const LumaImage& a, const LumaImage& b, const SsimParams& params = {});

// The normalised 1-D Gaussian of the SSIM window (sums to 1); the 2-D window is its outer product.
std::vector<double> ssim_gaussian_1d(uint32_t window, double sigma);

// Bitwise visibility error (the paper's metric): per light, the share of pixels whose bit differs.
struct BitError {
  uint64_t pixels = 0;                 // pixels compared
  std::vector<uint64_t> wrong;         // per light: pixels whose bit differs
  uint64_t wrong_bits() const;         // sum over lights
  double fraction() const;             // wrong bits / (pixels * lights); 0 when nothing was compared
  double light_fraction(uint32_t light) const;
};

// std::nullopt when the buffers differ in size or light count. Bits above the light count are ignored.
std::optional<BitError> visibility_bit_error(const VisibilityBuffer& a, const VisibilityBuffer& b);

}  // namespace dhr
