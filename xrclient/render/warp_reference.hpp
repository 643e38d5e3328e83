// CPU reference of the warp pass, in double, on plain arrays. The GPU pass
// (shaders/client/warp.comp) makes the same decisions in the same order:
//   depth == 0 (background)               -> unknown (kBackground)
//   no visibility buffer                  -> unknown (kNoData)
//   p = surface point of the pixel centre (depth -> eye space of the display camera -> world)
//   depth of p in the old eye <= min_depth -> unknown (kBehind)
//   (px, py) = p in the old camera's continuous pixel coordinates (centres at +0.5)
//   outside [0, W') x [0, H')            -> unknown (kOutside)
//   row floor(py) did not arrive          -> unknown (kMissingRow)
//   otherwise                             -> the old mask at (floor(px), floor(py)) (kKnown)
// Unknown pixels take every light bit of the buffer (all 32 without a buffer): the paper's "take as lit".
//
// Exactness: the GPU computes in float (eye-relative, so the error does not grow with the distance from the
// world origin), so a pixel whose continuous lookup coordinate lies within ~1e-4 px (test sizes; ~1e-3 px at
// 2k pixels per axis) of a pixel boundary, or whose old-eye depth is within ~1e-6 m of min_depth, may round
// the other way. `margin` reports, per pixel, how far the decision is from flipping; the tests make pixels
// with a margin under 2e-3 background (depth 0; under 2% of them) and then require GPU == CPU on every pixel.
#pragma once
#include <array>
#include <cstdint>
#include <glm/vec2.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "math/projection.hpp"
#include "visibility/visibility.hpp"
#include "render/render_camera.hpp"

namespace dhr::render {

// Values equal shader_interface.h's kClientStatus* constants.
enum class WarpStatus : uint8_t {
  kKnown = 0,
  kBackground = 1,
  kBehind = 2,
  kOutside = 3,
  kMissingRow = 4,
  kNoData = 5,
};
inline constexpr size_t kWarpStatusCount = 6;
const char* to_string(WarpStatus status);

// Per-status pixel counts, indexed by WarpStatus.
struct WarpCounts {
  std::array<uint64_t, kWarpStatusCount> by_status{};
  uint64_t operator[](WarpStatus s) const { return by_status[static_cast<size_t>(s)]; }
  // Surface pixels without a mask from the buffer (behind, outside, missing row, no data).
  uint64_t unknown_surface() const;
  uint64_t surface() const;  // every pixel but background
  bool operator==(const WarpCounts&) const = default;
};

// Mask for unknown pixels: every light bit of the buffer, all 32 without one.
uint32_t unknown_mask(const VisibilityBuffer* visibility);

// Error message when the visibility input cannot be used with the traced camera: bad camera, size mismatch,
// inconsistent data size or mask width, row_valid neither empty nor one entry per row.
std::optional<std::string> validate_visibility_input(const Camera& traced, const VisibilityBuffer& visibility,
                                                     std::span<const uint8_t> row_valid);

struct WarpInput {
  std::span<const float> depth;  // display width * height, row-major, reversed-Z (0 = background)
  Camera display;                // the camera the depth was rendered with
  Camera traced;                 // the guard-banded camera the visibility was traced for
  double near_plane = kDefaultNearPlane;
  double min_depth = kWarpMinDepth;
  const VisibilityBuffer* visibility = nullptr;  // null: nothing received yet
  std::span<const uint8_t> row_valid;            // empty (all rows) or one entry per old row, 0 = missing
};

struct WarpResult {
  Extent extent;
  std::vector<uint32_t> masks;       // per display pixel
  std::vector<WarpStatus> status;    // per display pixel
  std::vector<glm::dvec2> lookup;    // continuous old pixel coordinate (0,0 where none was computed)
  std::vector<double> margin;        // pixels (or 1e6 x metres for the behind test) to the nearest flip
  WarpCounts counts;
};

// Throws std::invalid_argument for inconsistent sizes or unusable cameras.
WarpResult warp_reference(const WarpInput& input);

}  // namespace dhr::render
