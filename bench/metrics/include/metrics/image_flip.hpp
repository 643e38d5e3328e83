// LDR-FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild, "FLIP: A Difference Evaluator
// for Alternating Images", HPG 2020): a per-pixel perceptual error in [0, 1] between two sRGB images, meant to
// predict what an observer flipping between them notices. Written from the paper's equations; the constants
// are the paper's and NVlabs' reference implementation's (listed, with their meaning, in image_flip.cpp).
//
// Pipeline, per image: sRGB8 -> linear RGB -> XYZ -> YCxCz; colour: each YCxCz channel filtered with its
// contrast-sensitivity kernel (sums of Gaussians, normalised to sum 1), back to linear RGB clamped to [0,1],
// CIELAB with the Hunt adjustment, HyAB distance, ^q_c and the p_c/p_t remap against the green-blue distance;
// features: edge and point detectors (first/second derivative of Gaussian) on the normalised achromatic
// channel. Per pixel: error = colour_error ^ (1 - feature_error).
//
// Borders: clamp-to-edge (replicate) padding for every filter, as the reference implementation does
// (OpenCV BORDER_REPLICATE in its Python version, index clamping in its C++ version).
// Filters are separable (the blue-yellow kernel as a weighted sum of two separable Gaussians); computed in
// double precision, single-threaded and deterministic. Results differ from the float32 reference by float
// rounding only (about 1e-6).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace dhr {

struct FlipParams {
  double pixels_per_degree = 67.0;  // the paper's default viewing condition (0.7 m from a 0.7 m wide 3840-px monitor)
};

struct FlipResult {
  uint32_t width = 0, height = 0;
  std::vector<float> error_map;  // width*height, row-major, each in [0,1]
  double mean = 0.0;             // mean of error_map
};

// Largest pixels_per_degree accepted: beyond it the filter kernels (radius ~0.14 ppd pixels) grow past any
// display (real ones are below ~300 ppd) and the cost with them.
inline constexpr double kFlipMaxPixelsPerDegree = 10000.0;

// LDR-FLIP between two sRGB-encoded RGBA8 images (alpha ignored), reference first.
// std::nullopt for size mismatch, zero size, spans of the wrong length, or pixels_per_degree not finite/positive
// (or above kFlipMaxPixelsPerDegree).
std::optional<FlipResult> flip_ldr(std::span<const uint8_t> reference_rgba8, std::span<const uint8_t> test_rgba8,
                                   uint32_t width, uint32_t height, const FlipParams& params = {});

}  // namespace dhr
