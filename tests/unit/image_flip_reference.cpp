#include "image_flip_reference.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dhr::flip_reference {
// Internal helpers are static; the header declares the rest.

// ------------------------------------------------ the published formulas, written out independently ---

// D65 white and XYZ->linear-RGB matrix as printed (9 digits) in NVlabs' reference implementation.
constexpr Vec3 kWhite{0.950428545, 1.0, 1.088900371};
constexpr std::array<Vec3, 3> kRgbToXyz{{{10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
                                         {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
                                         {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}}};
constexpr std::array<Vec3, 3> kXyzToRgb{{{3.241003275, -1.537398934, -0.498615861},
                                         {-0.969224334, 1.875930071, 0.041554224},
                                         {0.055639423, -0.204011202, 1.057148933}}};

static Vec3 mat_mul(const std::array<Vec3, 3>& m, const Vec3& v) {
  Vec3 out{};
  for (int r = 0; r < 3; ++r) out[r] = m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2];
  return out;
}

static double decode_srgb(uint8_t byte) {
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
static double colour_error_from_hyab(double distance) {
  const double qc = 0.7, pc = 0.4, pt = 0.95;
  const double cmax = std::pow(hyab_distance(hunt_lab({0, 1, 0}), hunt_lab({0, 0, 1})), qc);
  const double e = std::pow(distance, qc);
  return e < pc * cmax ? e * pt / (pc * cmax) : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0 - pt);
}

double uniform_closed_form(Rgb8 ref, Rgb8 test) {
  return colour_error_from_hyab(hyab_distance(hunt_lab(linear_rgb(ref)), hunt_lab(linear_rgb(test))));
}

// ------------------------------------------------------- direct (non-separable) FLIP, from the paper ---


struct Kernel2d {
  int r = 0;
  std::vector<double> k;  // (2r+1)^2, k[(j + r) * (2r+1) + (i + r)] at offset (i, j)
  double at(int i, int j) const { return k[static_cast<size_t>((j + r) * (2 * r + 1) + (i + r))]; }
};

static Grid correlate_clamped(const Grid& in, const Kernel2d& k) {
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

static Kernel2d csf_kernel(double ppd, double a1, double b1, double a2, double b2) {
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
static Kernel2d feature_kernel(double ppd, bool second_derivative, bool transpose) {
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

}  // namespace dhr::flip_reference
