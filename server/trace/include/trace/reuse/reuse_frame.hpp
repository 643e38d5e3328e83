// Reuse of traced visibility across frames (and sessions): what one traced eye leaves behind (ReuseFrame) and the
// two rules that take visibility from it instead of tracing (docs/server.md, "Reuse").
//
// A static surface point's visibility of a static light does not depend on the viewer (shared/DESIGN.md §5).
// 1. Whole 4x4 blocks, no ray at all (reuse_gather_block): the block's centre is found in the eye's previous trace
//    by iterating its reprojection; the traced pixels within reach of it must be uniform (one mesh, identical
//    masks, cells without a discontinuity: ReuseFrame::cell_mesh), land 0.75 to 1.5 new pixels apart, and lie
//    farther from any depth or surface discontinuity of that trace than anything in front of them could move across
//    the image between the two traces (the parallax bound: reuse_motion with the nearest depths around,
//    ReuseFrame::near), and farther from the image border than unseen geometry at the near plane could. Then no
//    other surface can cover the block; each pixel's point is where its ray meets the found pixel's tangent plane,
//    and its mask is theirs. Not when geometry crosses the near plane between the traces (the tracer's point query).
// 2. Per pixel-light pair, after the pixel's primary ray (reuse_lookup): the surface point X is projected into a
//    source trace (the eye's previous one, the other eye's, other sessions'); the four traced pixels around it must
//    be X's surface (reuse_same_surface, no sparser than 1.5 new pixels) and know the light's occlusion and agree
//    (a soft light: hold the same level; not in a scene that moves).
// Soft lights' samples accumulate: the record keeps each pixel's share and count of samples (SoftTally), and a traced
// soft pair on the previous trace's surface adds new samples to the corners' blend (reuse_soft_history).
// Anything else traces. One pixel in kRefreshPeriod is traced in full each frame (a 4x4 ordered dither that visits
// each pixel of a 4x4 block once in 16 frames), so a shadow feature that fell between the samples it was taken
// from is found again. Motion: surfaces on moving meshes are never taken from, a light that moved is traced again,
// and a block or pair whose shadow segments meet a moving mesh's box (then or now) is traced.
// What this cannot see: a surface that no traced pixel sampled (seen exactly edge-on) and that turns toward the eye
// by the next trace; docs/server.md, "Reuse", measures what that costs.
#pragma once
#include "math/projection.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace dhr::server {

// An axis-aligned box in the tracer's relative frame.
struct ReuseBox {
  glm::vec3 lo{0.0f};
  glm::vec3 hi{0.0f};
};

// A pixel of a ReuseFrame with no reusable surface (background, or a surface on a moving mesh).
inline constexpr uint32_t kNoReuseSurface = 0xFFFFFFFFu;

// One pixel in this many is traced in full each frame (the 4x4 dither: one pixel per 4x4 block).
inline constexpr uint32_t kRefreshPeriod = 16;

// Discontinuities are kept per cell of this many pixels square (ReuseFrame::edge_distance).
inline constexpr uint32_t kReuseCell = 4;
// ReuseFrame::near: the nearest depth of an occluding pixel within kNearRadius[k] pixels, k = 0 .. kNearLevels - 1
// (on cells of that size, each with its 8 neighbours), and over the whole frame. What slides over a point comes over an
// occluding pixel's place: across a discontinuity (both its sides occlude), or across a contour that forms where a
// curved surface (a neighbour's normal differs: dot below kReuseFlat) was seen nearly edge-on (|n . view| <=
// kReuseGrazing: a surface point's view direction turns by less than that while the eye moves less than
// kReuseGrazing times its distance, and a contour forms only where the view is edge-on); so within p pixels of the
// point when it moves p pixels. The rule takes a block only when the nearest occluding pixels within each radius
// cannot move farther than the radius below less the block's own reach (what lies within a radius but not the one
// below lies beyond that one; parallax within 16 pixels: the discontinuity clearance), and only while the eye moved
// less than kReuseGrazing times the nearest surface depth. The radii grow by 1.5 and 4/3 in turn: the closer they
// lie, the less the 3x3 cells' slack refuses (docs/performance.md, "Finer nearby-depth levels").
inline constexpr uint32_t kNearLevels = 9;
inline constexpr uint32_t kNearRadius[kNearLevels] = {16, 24, 32, 48, 64, 96, 128, 192, 256};
inline constexpr float kReuseGrazing = 0.35f;
inline constexpr float kReuseFlat = 0.99999f;

struct ReuseOptions {
  bool enabled = true;
  // Neighbours count as one surface when each is within this share of the pixel spacing of the others' tangent
  // planes and within neighbour_reach spacings of them.
  float plane_tolerance = 0.25f;
  float neighbour_reach = 2.5f;
  // The traced pixels taken from may be at most this many new pixels apart (a closer view traces).
  float max_magnification = 1.5f;
  bool refresh = true;        // trace the dithered kRefreshPeriod share in full (off: tests of the rules only)
  // Soft lights: a traced pair whose point lies on the surface of the eye's previous trace adds its first samples to
  // what that trace had accumulated there (SoftTally), at most this many samples kept (older ones weigh less once
  // it is reached); 0: every traced pair starts from nothing (the samples of one frame only).
  uint32_t soft_history = 128;
  // A pair with a history keeps the level its history rounds to while the accumulated share lies within half a level
  // plus this many levels of it (soft_level_hysteresis): new samples move the share a little every trace, and each
  // level that flips costs the codec bits. 0: the nearest level. Area room, 1984x1116, 90 frames of Gul User1,
  // 50 ms: 12.12 -> 10.56 Mbit/s; visibility_error +0.3 % at the client (docs/performance.md, "What a session
  // sends").
  float soft_hysteresis = 0.25f;
  bool whole_pixels = true;   // rule 1 (off: every pixel's primary ray is traced, rule 2 only)
  bool pairs = true;          // rule 2
};

// Pixel coordinates of a point (relative frame) in one camera, in float: pixel = (ax.d, ay.d) / (w.d) with
// d = X - eye, and w.d its depth along the view axis.
struct ReuseProjection {
  glm::vec3 eye{0.0f};
  glm::vec3 ax{0.0f}, ay{0.0f}, w{0.0f};
  float focal = 1.0f;  // the smaller of the camera's two focal lengths (pixels per unit tangent)

  // `eye` = the camera's position in the relative frame.
  static ReuseProjection of(const Camera& camera, const glm::vec3& eye);
  // False at or behind the eye plane.
  bool project(const glm::vec3& x, glm::vec2& out_pixel, float& out_depth) const;
};

// A soft light's accumulated samples at a pixel: the share that reached the light (share / 65535) of `samples`
// samples (0: nothing accumulated).
struct SoftTally {
  uint16_t share = 0;
  uint16_t samples = 0;
};

// What one traced eye leaves for later traces: its camera and, per pixel, the surface and its visibility.
// Positions and boxes are in the relative frame of the tracer that wrote it (only that tracer reads it back).
struct ReuseFrame {
  Camera camera;
  ReuseProjection projection;
  double scene_time = 0.0;
  uint32_t generation = 0;  // traces in this eye's chain so far: picks the dithered refresh pixels
  uint32_t lights = 0;      // lights of the traced layout
  uint32_t mask_bits = 0;   // its mask's bits (VisibilityLayout::total_bits)
  // Per light, two entries: its packed position_type and direction_range then (a light whose entries differ
  // now has moved: nothing of it is reused).
  std::vector<glm::vec4> light_state;
  std::vector<ReuseBox> moving_boxes;  // meshes on moving nodes then
  // Per pixel, row-major.
  std::vector<glm::vec3> position;   // surface point (relative frame)
  std::vector<glm::vec3> normal;     // unit geometric normal, on the viewer's side
  std::vector<glm::vec3> shading;    // unit shading normal (the light test's), flipped with the geometric one
  std::vector<uint32_t> mesh;        // kNoReuseSurface where nothing may be reused
  std::vector<uint32_t> mask;        // the traced mask (every field of the layout)
  std::vector<uint32_t> known;       // hard lights (bit = light index) whose occlusion is known here
  std::vector<uint32_t> reached;     // of those, the light is reached (not occluded)
  // Per pixel and soft light (pixel * tally_stride + the light's rank among the layout's soft lights), the
  // accumulated samples (ReuseOptions::soft_history); empty when the trace kept none.
  std::vector<SoftTally> tally;
  uint32_t tally_stride = 0;
  // With light slots (known and reached then hold fields, not lights): per pixel, the grid cell of its surface
  // point (LightSlots::cell_of), whose lights its fields are; empty without slots. Rule 2 takes answers only from
  // pixels of the query's cell, rule 1 only pixels whose point lies in the found pixel's cell.
  std::vector<uint32_t> region;
  // Per kReuseCell x kReuseCell cell: Chebyshev distance in cells to the nearest cell with a discontinuity
  // (0: this one has one; capped at 255), and the nearest depth of its occluding pixels (metres; kNearLevels).
  uint32_t cells_x = 0, cells_y = 0;
  std::vector<uint8_t> edge_distance;
  std::vector<float> cell_depth;
  // The nearest occluding depth within kNearRadius[k] pixels, per cell of that size (near_x[k] per row), and of
  // the frame; the nearest surface depth of the frame.
  std::vector<float> near[kNearLevels];
  uint32_t near_x[kNearLevels] = {};
  float nearest = 0.0f;
  float nearest_surface = 0.0f;
  std::vector<float> cell_surface_depth;  // per cell, its pixels' nearest depth (finish_reuse_distances' input)
  // Per cell: the mesh all its pixels share with identical mask, known and reached lights (those of its first
  // pixel), or kNoReuseSurface.
  std::vector<uint32_t> cell_mesh;

  bool valid() const { return !mesh.empty() && !edge_distance.empty(); }
  // Sizes the per-pixel arrays for `camera` (their contents are the tracer's to write: every pixel) and clears
  // the edge distances (finish_reuse_frame computes them).
  void reset(const Camera& camera, const glm::vec3& eye, uint32_t lights, uint32_t mask_bits, double scene_time,
             uint32_t generation);
};

// What one trace may take from (sources, tried in order) and where it leaves its own (record, not a source).
// Every frame must come from the same tracer (its relative frame and scene).
struct ReuseRequest {
  const ReuseFrame* previous = nullptr;   // this eye's last trace: whole pixels come from it; this is generation + 1
  std::vector<const ReuseFrame*> shared;  // other eyes' or sessions' traces, tried after `previous` for pairs
  ReuseFrame* record = nullptr;           // receives this trace's surfaces and answers (nullptr: none kept)
  ReuseOptions options;
};

// The lights of `frame` whose occlusion at a new surface point can be taken from it (rule 2), and their answers.
struct ReuseAnswer {
  uint32_t known = 0;
  uint32_t reached = 0;
  // Where the four neighbours were X's surface: the mask bits on which all four agree, and their common value (for
  // soft fields, taken only when every bit of a field agrees).
  uint32_t agree = 0;
  uint32_t mask = 0;
};

// The new pixel's surface point: position and unit geometric normal (relative frame), its mesh, and the new
// frame's pixel spacing there (metres per pixel).
struct ReuseQuery {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};
  uint32_t mesh = 0;
  float spacing = 0.0f;
  uint32_t region = 0;  // its light-slot cell, compared where the frame has regions (ReuseFrame::region)
};

// The 2x2 traced pixels of `frame` around a new surface point that passed rule 2's surface checks (X's mesh, one
// smooth surface with it, no sparser than options.max_magnification new pixels): their indices and bilinear weights.
struct ReuseCorners {
  size_t index[4] = {};
  float weight[4] = {};
};
bool reuse_corners(const ReuseFrame& frame, const ReuseQuery& query, const ReuseOptions& options,
                   ReuseCorners& out);

// What `frame` accumulated of the soft light of tally slot `slot` (ReuseFrame::tally) at the corners' point: the
// bilinear blend of the corners' tallies, weighted by their samples too (fraction, samples); samples 0 when the
// frame kept no tally there.
struct SoftHistory {
  float fraction = 0.0f;
  float samples = 0.0f;
};
// None either where the corners' shares differ by more than kSoftHistorySpread: a steep penumbra, where the blend
// at a reprojected point is off by more than what the samples would gain (accumulating anyway raised the area room's
// visibility_error by 6 % instead of lowering it; docs/performance.md, "Reuse").
// Corners weighing this little (a point reprojected onto a traced pixel's centre) do not count in that spread.
inline constexpr float kSoftHistorySpread = 1.0f / 7.0f;
inline constexpr float kSoftHistoryWeightFloor = 0.01f;
SoftHistory reuse_soft_history(const ReuseFrame& frame, const ReuseCorners& corners, uint32_t slot);

// A tally holding `history` and `visible` of `samples` new samples, at most `cap` samples (the history weighs
// cap - samples when the sum exceeds it).
SoftTally add_soft_samples(const SoftHistory& history, uint32_t visible, uint32_t samples, uint32_t cap);
inline float tally_fraction(const SoftTally& t) { return static_cast<float>(t.share) / 65535.0f; }

// The share to quantize for a pair whose accumulated share is `fraction` and whose history's was
// `history_fraction`: the history's nearest level (as a share) while `fraction` lies within 0.5 + `hysteresis`
// levels of it, else `fraction` (levels: kDefaultSoftLevels, visibility/soft_levels.hpp).
float soft_level_hysteresis(float fraction, float history_fraction, float hysteresis);

// Whether two traced surface points (positions, unit normals) are one smooth surface at `spacing` metres per
// pixel: normals within about 25 degrees, each within options.plane_tolerance spacings of the other's tangent plane
// and options.neighbour_reach spacings of the other.
bool reuse_same_surface(const glm::vec3& pa, const glm::vec3& na, const glm::vec3& pb, const glm::vec3& nb,
                        float spacing, const ReuseOptions& options);

// Rule 2 (motion not considered: see segment_misses_boxes). `candidates` limits the hard lights looked at; the
// agreeing mask bits are returned whenever the surface checks pass. reuse_answer: the same from corners found.
ReuseAnswer reuse_lookup(const ReuseFrame& frame, const ReuseQuery& query, uint32_t candidates,
                         const ReuseOptions& options);
ReuseAnswer reuse_answer(const ReuseFrame& frame, const ReuseCorners& corners, uint32_t candidates);

// How far the eye moved between `frame` and now, for the parallax bound: a point at depth z moves across the image
// by at most scale / (z - shift) pixels beyond what a point at infinity does (the eye's move times the focal length
// times the frustum's corner ray length, over the depth less the move).
struct ReuseMotion {
  float scale = 0.0f;  // pixel-metres
  float shift = 0.0f;  // metres
  // Per side of the frame's image (kReuseLeft, kReuseRight, kReuseTop, kReuseBottom: pixel column 0, column
  // width, row 0, row height), the nearest depth at which geometry no pixel of the frame saw can enter the image
  // from beyond that side: the near plane, or more when the caller knows nothing beyond that side of the frame's
  // frustum is that near the eyes (the tracer's point queries).
  std::array<float, 4> unseen_depth{static_cast<float>(kClipNearPlane), static_cast<float>(kClipNearPlane),
                                    static_cast<float>(kClipNearPlane), static_cast<float>(kClipNearPlane)};
};
enum ReuseSide : uint32_t { kReuseLeft = 0, kReuseRight = 1, kReuseTop = 2, kReuseBottom = 3 };
ReuseMotion reuse_motion(const ReuseFrame& frame, const ReuseProjection& now);

// A pixel taken whole (rule 1).
struct GatheredPixel {
  uint32_t mask = 0, known = 0, reached = 0, mesh = 0;
  glm::vec3 position{0.0f};  // the surface point under the new pixel centre
  glm::vec3 normal{0.0f};
  glm::vec3 shading{0.0f};
};

// Rule 1 for a 4x4 block at once: the traced pixel found for the block's centre (bx + 2, by + 2), with every cell
// within reach of it uniform (ReuseFrame::cell_mesh, the same for all) and clear of discontinuities by the
// parallax, and the traced pixels no sparser than options.max_magnification new pixels: true with that pixel's
// index in the frame (its mask, known and reached lights are every block pixel's; its tangent plane holds their
// surface points).
bool reuse_gather_block(const ReuseFrame& frame, const ReuseProjection& now, uint32_t bx, uint32_t by,
                        const ReuseMotion& motion, const ReuseOptions& options, glm::vec2& guess, size_t& out_pixel);


// Computes frame's edge distances, uniform cells and near depths from its per-pixel surfaces (rows [y0, y1) of
// cells for finish_reuse_cells, run by parallel workers; then finish_reuse_distances once).
void finish_reuse_cells(ReuseFrame& frame, uint32_t cell_y0, uint32_t cell_y1, const ReuseOptions& options);
void finish_reuse_distances(ReuseFrame& frame);

// The 4x4 ordered-dither matrix: consecutive generations refresh pixels spread over the block.
inline constexpr uint32_t kRefreshDither[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
// Whether pixel (x, y) is in this generation's dithered refresh share (traced in full). Inline: asked per pixel.
inline bool reuse_refresh_pixel(uint32_t x, uint32_t y, uint32_t generation) {
  return kRefreshDither[(y & 3u) * 4u + (x & 3u)] == generation % kRefreshPeriod;
}

// Whether the segment from `from` to `to` misses every box (each widened by `margin`).
bool segment_misses_boxes(const glm::vec3& from, const glm::vec3& to, const std::vector<ReuseBox>& boxes,
                          float margin);

}  // namespace dhr::server
