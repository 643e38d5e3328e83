// PSNR, SSIM (separable Gaussian window) and the bitwise visibility error.
#include "metrics/image_metrics.hpp"

#include <bit>
#include <cmath>
#include <limits>

namespace dhr {
namespace {

bool same_size(const LumaImage& a, const LumaImage& b) {
  return a.consistent() && b.consistent() && a.width == b.width && a.height == b.height && a.pixel_count() > 0;
}

// Valid-region correlation of `in` (w x h) with the separable window g (size k): (w-k+1) x (h-k+1).
std::vector<double> filter_valid(const std::vector<double>& in, uint32_t w, uint32_t h, const std::vector<double>& g) {
  const uint32_t k = static_cast<uint32_t>(g.size());
  const uint32_t ow = w - k + 1, oh = h - k + 1;
  std::vector<double> rows(static_cast<size_t>(ow) * h);
  for (uint32_t y = 0; y < h; ++y) {
    const double* src = &in[static_cast<size_t>(y) * w];
    for (uint32_t x = 0; x < ow; ++x) {
      double s = 0.0;
      for (uint32_t i = 0; i < k; ++i) s += g[i] * src[x + i];
      rows[static_cast<size_t>(y) * ow + x] = s;
    }
  }
  std::vector<double> out(static_cast<size_t>(ow) * oh);
  for (uint32_t y = 0; y < oh; ++y) {
    for (uint32_t x = 0; x < ow; ++x) {
      double s = 0.0;
      for (uint32_t i = 0; i < k; ++i) s += g[i] * rows[static_cast<size_t>(y + i) * ow + x];
      out[static_cast<size_t>(y) * ow + x] = s;
    }
  }
  return out;
}

}  // namespace

LumaImage luma_from_rgba8(std::span<const uint8_t> rgba, uint32_t width, uint32_t height) {
  LumaImage out;
  if (rgba.size() != static_cast<size_t>(width) * height * 4) return out;
  out.width = width;
  out.height = height;
  out.pixels.resize(out.pixel_count());
  for (size_t i = 0; i < out.pixels.size(); ++i) {
    out.pixels[i] = 0.299 * rgba[i * 4] + 0.587 * rgba[i * 4 + 1] + 0.114 * rgba[i * 4 + 2];
  }
  return out;
}

std::optional<double> psnr(const LumaImage& a, const LumaImage& b, double peak) {
  if (!same_size(a, b) || !(peak > 0.0)) return std::nullopt;
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = a.pixels[i] - b.pixels[i];
    sum += d * d;
  }
  const double mse = sum / static_cast<double>(a.pixels.size());
  if (mse == 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(peak * peak / mse);
}

std::vector<double> ssim_gaussian_1d(uint32_t window, double sigma) {
  std::vector<double> g(window);
  const double centre = (static_cast<double>(window) - 1.0) / 2.0;
  double sum = 0.0;
  for (uint32_t i = 0; i < window; ++i) {
    const double d = static_cast<double>(i) - centre;
    g[i] = std::exp(-d * d / (2.0 * sigma * sigma));
    sum += g[i];
  }
  for (double& v : g) v /= sum;
  return g;
}

std::optional<double> ssim(const LumaImage& a, const LumaImage& b, const SsimParams& params) {
  if (!same_size(a, b) || params.window == 0 || params.window % 2 == 0 || !(params.sigma > 0.0) ||
      !(params.dynamic_range > 0.0) || a.width < params.window || a.height < params.window) {
    return std::nullopt;
  }
  const uint32_t w = a.width, h = a.height;
  const std::vector<double> g = ssim_gaussian_1d(params.window, params.sigma);
  std::vector<double> aa(a.pixels.size()), bb(a.pixels.size()), ab(a.pixels.size());
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    aa[i] = a.pixels[i] * a.pixels[i];
    bb[i] = b.pixels[i] * b.pixels[i];
    ab[i] = a.pixels[i] * b.pixels[i];
  }
  const std::vector<double> mu_a = filter_valid(a.pixels, w, h, g);
  const std::vector<double> mu_b = filter_valid(b.pixels, w, h, g);
  const std::vector<double> e_aa = filter_valid(aa, w, h, g);
  const std::vector<double> e_bb = filter_valid(bb, w, h, g);
  const std::vector<double> e_ab = filter_valid(ab, w, h, g);
  const double c1 = (params.k1 * params.dynamic_range) * (params.k1 * params.dynamic_range);
  const double c2 = (params.k2 * params.dynamic_range) * (params.k2 * params.dynamic_range);
  double sum = 0.0;
  for (size_t i = 0; i < mu_a.size(); ++i) {
    const double ma = mu_a[i], mb = mu_b[i];
    const double va = e_aa[i] - ma * ma, vb = e_bb[i] - mb * mb, cov = e_ab[i] - ma * mb;
    sum += ((2.0 * ma * mb + c1) * (2.0 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
  }
  return sum / static_cast<double>(mu_a.size());
}

uint64_t BitError::wrong_bits() const {
  uint64_t total = 0;
  for (const uint64_t n : wrong) total += n;
  return total;
}

double BitError::fraction() const {
  const double bits = static_cast<double>(pixels) * static_cast<double>(wrong.size());
  return bits > 0.0 ? static_cast<double>(wrong_bits()) / bits : 0.0;
}

double BitError::light_fraction(uint32_t light) const {
  if (light >= wrong.size() || pixels == 0) return 0.0;
  return static_cast<double>(wrong[light]) / static_cast<double>(pixels);
}

std::optional<BitError> visibility_bit_error(const VisibilityBuffer& a, const VisibilityBuffer& b) {
  if (a.width != b.width || a.height != b.height || a.light_count != b.light_count ||
      a.data.size() != a.size_bytes() || b.data.size() != b.size_bytes()) {
    return std::nullopt;
  }
  BitError out;
  out.pixels = a.pixel_count();
  out.wrong.assign(a.light_count, 0);
  const uint32_t bits = a.light_bits();
  for (size_t p = 0; p < a.pixel_count(); ++p) {
    uint32_t diff = (a.mask_at(p) ^ b.mask_at(p)) & bits;
    while (diff != 0) {
      out.wrong[static_cast<size_t>(std::countr_zero(diff))] += 1;
      diff &= diff - 1;
    }
  }
  return out;
}

}  // namespace dhr
