// LDR-FLIP (Andersson et al., HPG 2020); the pipeline is summarised in image_flip.hpp.
//
// Constants, from the paper and NVlabs' reference implementation (github.com/NVlabs/flip):
//   colour:   q_c = 0.7 (exponent on the HyAB distance), p_c = 0.4, p_t = 0.95 (errors below p_c * c_max map
//             linearly to [0, p_t], the rest to [p_t, 1]); c_max = HyAB(Hunt(Lab(green)), Hunt(Lab(blue)))^q_c
//             for linear-RGB primaries green (0,1,0) and blue (0,0,1), the largest distance in the RGB cube.
//   CSF:      per channel s(x) = a1 sqrt(pi/b1) exp(-pi^2 x^2/b1) + a2 sqrt(pi/b2) exp(-pi^2 x^2/b2), x in
//             degrees, used radially in 2-D and normalised to sum 1: achromatic (a1, b1) = (1, 0.0047),
//             red-green (1, 0.0053), blue-yellow (34.1, 0.04) + (13.5, 0.025). One radius for all three:
//             ceil(3 sqrt(b_max / (2 pi^2)) ppd) pixels, b_max = 0.04 (10 px at 67 ppd).
//   features: w = 0.082 degrees (peak-to-trough of the edge detector = 2 standard deviations), so
//             sigma = 0.5 w ppd pixels, radius ceil(3 sigma); first (edges) and second (points) x-derivative of
//             the Gaussian, positive weights normalised to sum 1 and negative ones to -1; applied along x and
//             (transposed) along y on the normalised achromatic channel (Y + 16) / 116; feature error
//             (max(|d edge|, |d point|) / sqrt 2)^q_f with q_f = 0.5.
//   colour:   sRGB transfer function (IEC 61966-2-1), the exact rational sRGB->XYZ (D65) matrix, its inverse
//             computed here, reference white = XYZ of linear RGB (1,1,1); CIELAB with delta = 6/29; Hunt
//             adjustment a' = 0.01 L a, b' = 0.01 L b; HyAB = |dL| + sqrt(da^2 + db^2).
//
// The 2-D kernels are separable: a Gaussian is a product of 1-D Gaussians, the blue-yellow CSF a weighted sum of
// two such products, and the reference's sign-wise normalisation of a derivative-of-Gaussian kernel d(x) g(y)
// factors into a sign-wise normalised 1-D d(x) times a 1-D g(y) normalised to sum 1.
#include "metrics/image_flip.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace dhr {
namespace {

constexpr double kQc = 0.7, kPc = 0.4, kPt = 0.95;
constexpr double kQf = 0.5, kFeatureWidthDegrees = 0.082;

struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfAchromatic{1.0, 0.0047, 0.0, 1e-5};
constexpr Csf kCsfRedGreen{1.0, 0.0053, 0.0, 1e-5};
constexpr Csf kCsfBlueYellow{34.1, 0.04, 13.5, 0.025};
constexpr double kCsfMaxB = 0.04;

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;
using Kernel = std::vector<double>;  // 2r+1 taps, tap i at offset i - r
using Plane = std::vector<double>;   // width * height, row-major

// ---------------------------------------------------------------------------------------------- colour ---

constexpr Mat3 kLinearRgbToXyz{{{10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
                                {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
                                {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}}};

Vec3 mul(const Mat3& m, const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

// Inverse through the adjugate; the sRGB matrix is far from singular.
Mat3 inverse(const Mat3& m) {
  Mat3 adj{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
      adj[r][c] = m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1];
    }
  }
  const double det = m[0][0] * adj[0][0] + m[0][1] * adj[1][0] + m[0][2] * adj[2][0];
  for (auto& row : adj) {
    for (double& v : row) v /= det;
  }
  return adj;
}

const Mat3& xyz_to_linear_rgb_matrix() {
  static const Mat3 m = inverse(kLinearRgbToXyz);
  return m;
}

// The white point the matrix maps linear RGB (1,1,1) to: D65, Y = 1.
Vec3 reference_white() { return mul(kLinearRgbToXyz, {1.0, 1.0, 1.0}); }

double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

Vec3 xyz_to_ycxcz(const Vec3& xyz, const Vec3& white) {
  const double x = xyz[0] / white[0], y = xyz[1] / white[1], z = xyz[2] / white[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Vec3 ycxcz_to_xyz(const Vec3& ycxcz, const Vec3& white) {
  const double y = (ycxcz[0] + 16.0) / 116.0;
  return {(y + ycxcz[1] / 500.0) * white[0], y * white[1], (y - ycxcz[2] / 200.0) * white[2]};
}

double lab_f(double t) {
  constexpr double delta = 6.0 / 29.0;
  return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
}

// CIELAB followed by the Hunt adjustment (chroma scaled by 0.01 L: dark colours look less colourful).
Vec3 hunt_lab_from_linear_rgb(const Vec3& rgb, const Vec3& white) {
  const Vec3 xyz = mul(kLinearRgbToXyz, rgb);
  const double fx = lab_f(xyz[0] / white[0]), fy = lab_f(xyz[1] / white[1]), fz = lab_f(xyz[2] / white[2]);
  const double l = 116.0 * fy - 16.0;
  return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

double hyab(const Vec3& p, const Vec3& q) {
  const double da = p[1] - q[1], db = p[2] - q[2];
  return std::abs(p[0] - q[0]) + std::sqrt(da * da + db * db);
}

// q_c-powered HyAB distance -> [0, 1]: linear to p_t up to p_c * c_max, then linear to 1 at c_max.
double remap_colour_error(double powered, double cmax) {
  const double knee = kPc * cmax;
  if (powered < knee) return powered * (kPt / knee);
  return kPt + (powered - knee) / (cmax - knee) * (1.0 - kPt);
}

double colour_cmax(const Vec3& white) {
  return std::pow(hyab(hunt_lab_from_linear_rgb({0.0, 1.0, 0.0}, white),
                       hunt_lab_from_linear_rgb({0.0, 0.0, 1.0}, white)),
                  kQc);
}

// --------------------------------------------------------------------------------------------- kernels ---

// exp(log_w - max) normalised to sum 1 over the taps whose log_w is finite (others get 0). Working from logs
// keeps tiny ppd (where the tails underflow) from dividing zero by zero.
Kernel normalised_from_logs(const std::vector<double>& log_w) {
  double top = -INFINITY;
  for (double l : log_w) top = std::max(top, l);
  Kernel k(log_w.size(), 0.0);
  if (!std::isfinite(top)) return k;
  double sum = 0.0;
  for (size_t i = 0; i < k.size(); ++i) {
    k[i] = std::exp(log_w[i] - top);
    sum += k[i];
  }
  for (double& v : k) v /= sum;
  return k;
}

// Sign-wise normalisation: the taps of `value` with positive sign sum to 1, the negative ones to -1. The
// magnitudes come as logs (value = sign * exp(log_mag)).
Kernel sign_normalised(const std::vector<int>& sign, const std::vector<double>& log_mag) {
  Kernel out(sign.size(), 0.0);
  for (int s : {1, -1}) {
    std::vector<double> logs(sign.size(), -INFINITY);
    for (size_t i = 0; i < sign.size(); ++i) {
      if (sign[i] == s) logs[i] = log_mag[i];
    }
    const Kernel part = normalised_from_logs(logs);
    for (size_t i = 0; i < out.size(); ++i) out[i] += s * part[i];
  }
  return out;
}

// 1-D factor of a CSF Gaussian exp(-pi^2 x^2 / b), x = offset / ppd degrees, normalised to sum 1; `raw_sum`
// returns the unnormalised sum (needed to weigh the two terms of the blue-yellow CSF).
Kernel csf_gaussian(int radius, double ppd, double b, double& raw_sum) {
  std::vector<double> logs(static_cast<size_t>(2 * radius + 1));
  raw_sum = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    const double x = i / ppd;
    logs[static_cast<size_t>(i + radius)] = -std::numbers::pi * std::numbers::pi * x * x / b;
    raw_sum += std::exp(logs[static_cast<size_t>(i + radius)]);
  }
  return normalised_from_logs(logs);
}

// A channel's CSF as w1 * (g1 x g1) + w2 * (g2 x g2), w1 + w2 = 1 (w2 = 0 and g2 empty for one Gaussian).
struct CsfFilter {
  Kernel g1, g2;
  double w1 = 1.0, w2 = 0.0;
};

CsfFilter make_csf_filter(const Csf& csf, int radius, double ppd) {
  CsfFilter f;
  double sum1 = 0.0, sum2 = 0.0;
  f.g1 = csf_gaussian(radius, ppd, csf.b1, sum1);
  // The 2-D term a sqrt(pi/b) e(x) e(y) sums to a sqrt(pi/b) * sum1^2 over the square kernel.
  const double mass1 = csf.a1 * std::sqrt(std::numbers::pi / csf.b1) * sum1 * sum1;
  if (csf.a2 == 0.0) return f;
  f.g2 = csf_gaussian(radius, ppd, csf.b2, sum2);
  const double mass2 = csf.a2 * std::sqrt(std::numbers::pi / csf.b2) * sum2 * sum2;
  f.w1 = mass1 / (mass1 + mass2);
  f.w2 = mass2 / (mass1 + mass2);
  return f;
}

struct FeatureKernels {
  Kernel gaussian, edge, point;
};

FeatureKernels make_feature_kernels(double ppd) {
  const double sd = 0.5 * kFeatureWidthDegrees * ppd;
  const int radius = static_cast<int>(std::ceil(3.0 * sd));
  const size_t n = static_cast<size_t>(2 * radius + 1);
  std::vector<double> log_g(n);
  std::vector<int> edge_sign(n), point_sign(n);
  std::vector<double> edge_log(n, -INFINITY), point_log(n, -INFINITY);
  for (int i = -radius; i <= radius; ++i) {
    const size_t k = static_cast<size_t>(i + radius);
    const double x = i;
    log_g[k] = -x * x / (2.0 * sd * sd);
    // Edge detector: -x g(x). Point detector: (x^2/sd^2 - 1) g(x).
    edge_sign[k] = (x < 0.0) - (x > 0.0);
    if (x != 0.0) edge_log[k] = std::log(std::abs(x)) + log_g[k];
    const double p = x * x / (sd * sd) - 1.0;
    point_sign[k] = (p > 0.0) - (p < 0.0);
    if (p != 0.0) point_log[k] = std::log(std::abs(p)) + log_g[k];
  }
  return {normalised_from_logs(log_g), sign_normalised(edge_sign, edge_log), sign_normalised(point_sign, point_log)};
}

// ------------------------------------------------------------------------------------------- filtering ---

// Planes are allocated once per call and reused: at 1280x720 one plane is 7 MB, and fresh allocations (page
// faults and zeroing) otherwise cost more than the arithmetic.
struct Image2d {
  uint32_t w = 0, h = 0;
  size_t size() const { return static_cast<size_t>(w) * h; }
};

// out[x] = sum_i k[i] * rows[i][x] for x in [0, w): four outputs at a time in registers (independent chains
// hide the add latency, no per-tap stores); every output sums its taps in order, so the result does not depend
// on the blocking.
void correlate_block(const std::vector<const double*>& rows, const Kernel& k, double* out, uint32_t w) {
  uint32_t x = 0;
  for (; x + 4 <= w; x += 4) {
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    for (size_t i = 0; i < k.size(); ++i) {
      const double* src = rows[i] + x;
      s0 += k[i] * src[0];
      s1 += k[i] * src[1];
      s2 += k[i] * src[2];
      s3 += k[i] * src[3];
    }
    out[x] = s0;
    out[x + 1] = s1;
    out[x + 2] = s2;
    out[x + 3] = s3;
  }
  for (; x < w; ++x) {
    double s = 0.0;
    for (size_t i = 0; i < k.size(); ++i) s += k[i] * rows[i][x];
    out[x] = s;
  }
}

// Correlation along rows, clamp-to-edge (the row is copied into a padded buffer).
void filter_rows(const Plane& in, Plane& out, Image2d dim, const Kernel& k, std::vector<double>& pad) {
  const size_t r = k.size() / 2;
  pad.resize(dim.w + 2 * r);
  std::vector<const double*> taps(k.size());
  for (size_t i = 0; i < k.size(); ++i) taps[i] = &pad[i];
  for (uint32_t y = 0; y < dim.h; ++y) {
    const double* src = &in[static_cast<size_t>(y) * dim.w];
    for (size_t i = 0; i < pad.size(); ++i) pad[i] = src[i < r ? 0 : std::min<size_t>(i - r, dim.w - 1)];
    correlate_block(taps, k, &out[static_cast<size_t>(y) * dim.w], dim.w);
  }
}

// Correlation along columns, clamp-to-edge (rows above and below the image repeat the edge rows).
void filter_cols(const Plane& in, Plane& out, Image2d dim, const Kernel& k) {
  const long r = static_cast<long>(k.size() / 2), last = static_cast<long>(dim.h) - 1;
  std::vector<const double*> taps(k.size());
  for (uint32_t y = 0; y < dim.h; ++y) {
    for (size_t i = 0; i < k.size(); ++i) {
      const long yy = std::clamp(static_cast<long>(y) + static_cast<long>(i) - r, 0L, last);
      taps[i] = &in[static_cast<size_t>(yy) * dim.w];
    }
    correlate_block(taps, k, &out[static_cast<size_t>(y) * dim.w], dim.w);
  }
}

struct Scratch {
  Plane a, b, c, d;
  std::vector<double> pad;
  explicit Scratch(size_t n) : a(n), b(n), c(n), d(n) {}
};

// CSF filtering of `plane` in place (uses scratch a and b).
void filter_csf(Plane& plane, Image2d dim, const CsfFilter& f, Scratch& s) {
  if (f.w2 != 0.0) {
    filter_rows(plane, s.a, dim, f.g2, s.pad);
    filter_cols(s.a, s.b, dim, f.g2);
  }
  filter_rows(plane, s.a, dim, f.g1, s.pad);
  filter_cols(s.a, plane, dim, f.g1);
  if (f.w2 == 0.0) return;
  for (size_t i = 0; i < plane.size(); ++i) plane[i] = f.w1 * plane[i] + f.w2 * s.b[i];
}

// -------------------------------------------------------------------------------------------- pipeline ---

struct Filters {
  CsfFilter achromatic, red_green, blue_yellow;
  FeatureKernels features;
};

Filters make_filters(double ppd) {
  const int radius =
      static_cast<int>(std::ceil(3.0 * std::sqrt(kCsfMaxB / (2.0 * std::numbers::pi * std::numbers::pi)) * ppd));
  return {make_csf_filter(kCsfAchromatic, radius, ppd), make_csf_filter(kCsfRedGreen, radius, ppd),
          make_csf_filter(kCsfBlueYellow, radius, ppd), make_feature_kernels(ppd)};
}

// What the final combination needs of one image: Hunt-adjusted CIELAB of the CSF-filtered image, and the
// edge and point detector magnitudes.
struct Perceived {
  std::vector<Vec3> lab;
  Plane edge, point;
};

void to_ycxcz(std::span<const uint8_t> rgba, const Vec3& white, Plane& y, Plane& cx, Plane& cz) {
  std::array<double, 256> linear{};
  for (size_t i = 0; i < linear.size(); ++i) linear[i] = srgb_to_linear(static_cast<double>(i) / 255.0);
  for (size_t i = 0; i < y.size(); ++i) {
    const Vec3 rgb{linear[rgba[4 * i]], linear[rgba[4 * i + 1]], linear[rgba[4 * i + 2]]};
    const Vec3 v = xyz_to_ycxcz(mul(kLinearRgbToXyz, rgb), white);
    y[i] = v[0];
    cx[i] = v[1];
    cz[i] = v[2];
  }
}

// Edge and point magnitudes of the normalised achromatic channel (Y + 16) / 116 = Y / Y_white. The x-direction
// responses are derivative-along-rows then Gaussian-along-columns, the y-direction ones the reverse.
void feature_magnitudes(const Plane& ycxcz_y, Image2d dim, const FeatureKernels& k, Scratch& s, Perceived& out) {
  Plane& achromatic = s.d;
  for (size_t i = 0; i < achromatic.size(); ++i) achromatic[i] = (ycxcz_y[i] + 16.0) / 116.0;
  filter_rows(achromatic, s.c, dim, k.gaussian, s.pad);  // s.c: rows smoothed, for the y derivatives
  for (int order = 1; order <= 2; ++order) {
    const Kernel& derivative = order == 1 ? k.edge : k.point;
    filter_rows(achromatic, s.a, dim, derivative, s.pad);
    filter_cols(s.a, s.b, dim, k.gaussian);  // s.b: d/dx
    filter_cols(s.c, s.a, dim, derivative);  // s.a: d/dy
    Plane& magnitude = order == 1 ? out.edge : out.point;
    for (size_t i = 0; i < magnitude.size(); ++i) magnitude[i] = std::sqrt(s.b[i] * s.b[i] + s.a[i] * s.a[i]);
  }
}

Perceived perceive(std::span<const uint8_t> rgba, Image2d dim, const Filters& f, const Vec3& white, Scratch& s,
                   Plane& y, Plane& cx, Plane& cz) {
  Perceived p{std::vector<Vec3>(dim.size()), Plane(dim.size()), Plane(dim.size())};
  to_ycxcz(rgba, white, y, cx, cz);
  feature_magnitudes(y, dim, f.features, s, p);  // on the unfiltered image, before y is filtered in place
  filter_csf(y, dim, f.achromatic, s);
  filter_csf(cx, dim, f.red_green, s);
  filter_csf(cz, dim, f.blue_yellow, s);
  for (size_t i = 0; i < p.lab.size(); ++i) {
    // Back to linear RGB, clamped to the displayable cube, then Hunt-adjusted CIELAB.
    Vec3 rgb = mul(xyz_to_linear_rgb_matrix(), ycxcz_to_xyz({y[i], cx[i], cz[i]}, white));
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
    p.lab[i] = hunt_lab_from_linear_rgb(rgb, white);
  }
  return p;
}

bool valid_arguments(std::span<const uint8_t> a, std::span<const uint8_t> b, uint32_t w, uint32_t h, double ppd) {
  const size_t bytes = static_cast<size_t>(w) * h * 4;
  return w > 0 && h > 0 && a.size() == bytes && b.size() == bytes && std::isfinite(ppd) && ppd > 0.0 &&
         ppd <= kFlipMaxPixelsPerDegree;
}

}  // namespace

std::optional<FlipResult> flip_ldr(std::span<const uint8_t> reference_rgba8, std::span<const uint8_t> test_rgba8,
                                   uint32_t width, uint32_t height, const FlipParams& params) {
  if (!valid_arguments(reference_rgba8, test_rgba8, width, height, params.pixels_per_degree)) return std::nullopt;
  const Image2d dim{width, height};
  const size_t pixels = dim.size();
  const Vec3 white = reference_white();
  const Filters filters = make_filters(params.pixels_per_degree);
  Scratch scratch(pixels);
  Plane y(pixels), cx(pixels), cz(pixels);
  const Perceived ref = perceive(reference_rgba8, dim, filters, white, scratch, y, cx, cz);
  const Perceived test = perceive(test_rgba8, dim, filters, white, scratch, y, cx, cz);

  const double cmax = colour_cmax(white);
  FlipResult result;
  result.width = width;
  result.height = height;
  result.error_map.resize(pixels);
  double sum = 0.0;
  for (size_t i = 0; i < pixels; ++i) {
    const double colour = remap_colour_error(std::pow(hyab(ref.lab[i], test.lab[i]), kQc), cmax);
    const double feature_diff =
        std::max(std::abs(ref.edge[i] - test.edge[i]), std::abs(ref.point[i] - test.point[i]));
    // Magnitudes of kernels with unit positive and negative mass on [0,1] data differ by at most sqrt 2; the
    // min only guards rounding.
    const double feature = std::min(1.0, std::pow(feature_diff / std::numbers::sqrt2, kQf));
    // c_max bounds HyAB over the RGB cube, so the clamp only guards rounding.
    const float e = static_cast<float>(std::clamp(std::pow(colour, 1.0 - feature), 0.0, 1.0));
    result.error_map[i] = e;
    sum += static_cast<double>(e);
  }
  result.mean = sum / static_cast<double>(pixels);
  return result;
}

}  // namespace dhr
