// CPU reference of the warp pass, in double, on plain arrays. The GPU pass (shaders/client/warp.comp) makes
// the same decisions in the same order. Per display pixel, for source 0 (this eye's newest buffer):
//   depth == 0 (background)                  -> kBackground (all bits)
//   no visibility buffer                     -> kNoData
//   p = surface point of the pixel centre (depth -> eye space of the display camera -> world)
//   depth of p in the old eye <= min_depth    -> kBehind
//   (px, py) = p in the old camera's continuous pixel coordinates (centres at +0.5)
//   outside [0, W') x [0, H')               -> kOutside
//   samples: nearest (the paper): the old pixel (floor(px), floor(py)); bilinear: the 2x2 old pixels around
//     (px - 0.5, py - 0.5) with bilinear weights. A sample is used when it lies in the buffer, its row
//     arrived, and (depth test) the old surface there lies within plane_tolerance of the tangent plane of
//     this pixel's surface (old depth from the traced camera's depth, the plane from the display normal).
//   no sample in an arrived row              -> kMissingRow
//   no sample used                           -> kDisoccluded
//   otherwise kKnown: bits all used samples agree on take that value; the others the bilinear vote
//     (set when 2 * weight of the samples with the bit >= weight of the used samples), or with shadow_edges
//     the shadow maps' bit. With shadow_first, every bit the shadow maps are confident about (unless a texel
//     is coarser than a display pixel at the point and the 2x2 texels around the lookup decide differently)
//     takes the shadow maps' bit, unless the lookup is exact (within 0.02 px of an old pixel centre).
// A surface pixel that source 0 does not fill tries source 1 (other_eye) the same way (fill kOtherEye), then
// source 2, this eye's previous buffer (older_buffer: fill kOlder), then (neighbour_fill, with the depth test
// and source 0's traced depth, when source 0's lookup was outside, in missing rows or disoccluded) the old
// pixels of source 0 within kNeighbourRadius (Chebyshev) of floor(px, py) whose row arrived and whose surface
// passes the depth test's plane check: the one whose centre is nearest (px, py) gives its whole mask (ties:
// the first in row-major order; fill kNeighbour), then the shadow maps (shadow_fill: fill kShadowMap), else
// takes every light bit of source 0's buffer (all 32 without one): the paper's "take as lit".
//
// Exactness: the GPU computes in float (eye-relative, so the error does not grow with the distance from the
// world origin), so a decision close to flipping (a lookup within ~1e-4 px of a pixel boundary or centre,
// an old-eye depth within ~1e-6 m of min_depth, a plane distance at the tolerance, a vote tie, a shadow
// decision at a face or texel boundary or the bias) may go the other way. `margin` reports, per pixel, how far
// its decisions are from flipping; the tests make pixels with a margin under 2e-3 background and then require
// GPU == CPU on every pixel.
#pragma once
#include "plan/shipped_defaults.hpp"
#include "plan/warp_choice.hpp"
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
#include "render/shadow_maps.hpp"
#include "scene/scene.hpp"
#include "shaders/shader_interface.h"

namespace dhr::render {

// Values equal shader_interface.h's kClientStatus* constants.
enum class WarpStatus : uint8_t {
  kKnown = 0,
  kBackground = 1,
  kBehind = 2,
  kOutside = 3,
  kMissingRow = 4,
  kNoData = 5,
  kDisoccluded = 6,
};
inline constexpr size_t kWarpStatusCount = 7;
const char* to_string(WarpStatus status);

// How a surface pixel without a mask from its own eye's buffer was filled (kClientFill*).
enum class WarpFill : uint8_t { kNone = 0, kOtherEye = 1, kShadowMap = 2, kOlder = 3, kNeighbour = 4 };
inline constexpr int kNeighbourRadius = 2;  // shader_interface.h's kClientWarpNeighbourRadius

// Per-status pixel counts, indexed by WarpStatus, and the fills.
struct WarpCounts {
  std::array<uint64_t, kWarpStatusCount> by_status{};
  uint64_t filled_other_eye = 0;    // surface pixels source 0 could not fill, filled by the other eye
  uint64_t filled_shadow_map = 0;   // ... by the shadow maps
  uint64_t filled_older = 0;        // ... by this eye's previous buffer
  uint64_t filled_neighbour = 0;    // ... by the nearest old pixel of source 0 on the pixel's tangent plane
  uint64_t edges_shadow_map = 0;    // known pixels whose undecided bits took the shadow maps
  uint64_t shadow_overrides = 0;    // known pixels where a confident shadow-map bit replaced an agreed one
  uint64_t motion_unknown = 0;      // pixels whose chosen source had bits motion made unknown (settings.motion)
  uint64_t operator[](WarpStatus s) const { return by_status[static_cast<size_t>(s)]; }
  // Surface pixels without a mask from their own eye's buffer (behind, outside, missing row, no data,
  // disoccluded), filled or not.
  uint64_t unknown_surface() const;
  uint64_t unfilled() const {
    return unknown_surface() - filled_other_eye - filled_shadow_map - filled_older - filled_neighbour;
  }
  uint64_t surface() const;  // every pixel but background
  bool operator==(const WarpCounts&) const = default;
};

// Which of the warp's ingredients are on. Default: the paper's warp (nearest sample, no depth test, no fills).
struct WarpSettings {
  bool bilinear = false;      // 2x2 samples and a bilinear vote instead of the nearest old pixel
  bool depth_test = false;    // reject samples whose old surface is off this pixel's tangent plane
  bool other_eye = false;     // fill from the other eye's newest buffer
  bool older_buffer = false;  // then from this eye's previous buffer
  bool neighbour_fill = false;  // then from the nearest old pixel on the tangent plane (needs depth_test)
  bool shadow_fill = false;   // fill the rest from the client's shadow maps
  bool shadow_edges = false;  // bits the samples disagree on from the shadow maps
  bool shadow_first = false;  // bits the shadow maps are confident about from the shadow maps
  // Bits that motion since the chosen source's scene time may have changed (WarpInput::motion, warp_motion.hpp)
  // are unknown: they take the shadow maps where any shadow setting is on, else the vote.
  bool motion = false;
  double plane_tolerance_rel = 0.02;  // metres per metre of depth
  double plane_tolerance_abs = 0.01;  // metres
  // depth_test: the traced depth is rendered at 1 / depth_scale of the traced camera's resolution per axis
  // (depth_camera); old pixel (a, b) tests the surface its texel (a, b) / depth_scale shows. 1: every old pixel.
  uint32_t depth_scale = 1;
  // depth_test: the traced depth is made from this eye's previous display frame's depth, moved into the traced
  // camera (render/traced_depth_splat.hpp), instead of a raster pass of the traced camera. Until the eye has
  // displayed a frame (and after a resize) there is none: that frame runs without the test.
  bool depth_splat = false;
  // With bilinear: a hard light's bit that any arrived old pixel within edge_band pixels (Chebyshev) of a used
  // sample disagrees on is undecided, as if the samples disagreed (render/warp_edges.hpp); 0: the 2x2 samples
  // alone. Exact lookups keep their pixel's mask. At most kMaxEdgeBand.
  uint32_t edge_band = 0;
  // With bilinear, soft fields shade with their share blended from the used samples' band shares (each source's
  // levels reconstructed once: render/soft_bands.hpp; shaders/client/bilinear_warp.h's warp_soft_blend) instead of
  // their level; the masks are unchanged.
  bool soft_refine = false;
  static WarpSettings full();  // every ingredient on
  // Server bits first: 2x2 bilinear samples, bits they all agree on from the server, the others and pixels
  // without a usable sample from the shadow maps; no depth test, so no traced depth: the forward pass runs it.
  // The edge band is the shipped one (client::shipped::kEdgeBand) unless given.
  static WarpSettings server_edges(uint32_t edge_band = client::shipped::kEdgeBand);
  // server_edges() with the depth test against a traced depth at 1 / depth_scale resolution: samples whose traced
  // surface is off the pixel's tangent plane are not used (none left: disoccluded, from the shadow maps).
  static WarpSettings server_edges_depth(uint32_t depth_scale, uint32_t edge_band = client::shipped::kEdgeBand);
  // The settings the forward pass runs (kServerEdges): server_edges(), with or without the depth test, any band.
  bool is_server_edges() const;
  bool uses_shadow_maps() const { return shadow_fill || shadow_edges || shadow_first; }
  // These settings with no ingredient that reads the client's shadow maps (a scene whose lights share light slots
  // has none: undecided bits then take the samples' vote, unfilled pixels are lit).
  WarpSettings without_shadow_maps() const {
    WarpSettings w = *this;
    w.shadow_fill = w.shadow_edges = w.shadow_first = false;
    return w;
  }
  bool operator==(const WarpSettings&) const = default;
};

// The settings of a --warp choice (paper: WarpSettings{}; resolved: kAuto throws std::invalid_argument) with
// --depth-scale and --traced-depth (edges-depth, full) and --edge-band: one mapping for dhr-xrclient's command line,
// client_bench's configurations and dhr-eval's `default`.
WarpSettings warp_settings_for(client::WarpChoice choice, uint32_t depth_scale,
                               uint32_t edge_band = client::shipped::kEdgeBand,
                               client::TracedDepth traced_depth = client::shipped::kTracedDepth);

// The camera a traced depth is rendered with at 1 / scale of `traced`'s resolution per axis: the same eye and
// top-left tangents, extent ceil(width / scale) x ceil(height / scale), its texel t covering old pixels
// t * scale .. t * scale + scale - 1 (the right and bottom tangents grow to whole texels). scale 1: `traced`.
// Throws std::invalid_argument for scale 0 or above 16.
Camera depth_camera(const Camera& traced, uint32_t scale);

// Mask for unknown pixels: every light lit. Without soft lights every bit of the buffer, all 32 without one; with
// them the layout's all-lit mask (a soft field's top level, not all its bits: Gray 0b111 is level 5).
uint32_t unknown_mask(const VisibilityBuffer* visibility, std::span<const SceneLight> lights);

// Whether `traced` was traced from `display`'s eye position (within 1e-9 m; the warp's kClientSourceSameEye).
bool same_eye(const Camera& display, const Camera& traced);

// Error message when the visibility input cannot be used with the traced camera: bad camera, size mismatch,
// inconsistent data size or mask width, row_valid neither empty nor one entry per row.
std::optional<std::string> validate_visibility_input(const Camera& traced, const VisibilityBuffer& visibility,
                                                     std::span<const uint8_t> row_valid);

// One visibility buffer as the warp reads it.
struct WarpSource {
  const VisibilityBuffer* visibility = nullptr;  // null: none
  Camera traced;                                 // the guard-banded camera it was traced for
  std::span<const uint8_t> row_valid;            // empty (all rows) or one entry per old row, 0 = missing
  std::span<const float> traced_depth;           // depth_camera(traced, settings.depth_scale)'s depth (reversed-Z);
                                                 // empty: no depth test
};

struct WarpInput {
  std::span<const float> depth;        // display width * height, row-major, reversed-Z (0 = background)
  std::span<const glm::vec3> normals;  // display width * height world normals; may be empty unless needed
  Camera display;                      // the camera the depth was rendered with
  double near_plane = kDefaultNearPlane;
  double min_depth = kWarpMinDepth;
  std::array<WarpSource, 3> sources;   // this eye's newest buffer, the other eye's, this eye's previous
  WarpSettings settings;
  const ShadowReference* shadow = nullptr;  // needed when a shadow setting is on
  std::span<const SceneLight> lights;       // for the shadow lookups
  const shader::ClientWarpMotion* motion = nullptr;  // settings.motion: what moved (warp_motion.hpp); null: nothing
};

struct WarpResult {
  Extent extent;
  std::vector<uint32_t> masks;       // per display pixel
  std::vector<WarpStatus> status;    // per display pixel
  std::vector<WarpFill> fill;        // per display pixel
  std::vector<glm::dvec2> lookup;    // source 0's continuous old pixel coordinate (0,0 where none was computed)
  std::vector<double> margin;        // distance to the nearest flip of any decision (see the header comment)
  std::vector<uint32_t> soft;        // per display pixel: refined soft shares (soft_refine.hpp; none without)
  WarpCounts counts;
};

// Throws std::invalid_argument for inconsistent sizes or unusable cameras.
WarpResult warp_reference(const WarpInput& input);

}  // namespace dhr::render
