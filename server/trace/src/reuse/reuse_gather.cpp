// Rule 1 of trace/reuse/reuse_frame.hpp: whole pixels found in the eye's previous trace, and the discontinuity
// distances that bound where it holds.
#include "trace/reuse/reuse_frame.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dhr::server {
namespace {

constexpr int kGatherIterations = 4;
// A whole block is taken only where neighbouring traced pixels land at least this many new pixels apart along
// both image axes.
constexpr float kMinBlockSpacing = 0.75f;
// The search stops at a traced pixel whose point lands within this many new pixels of the block's centre along each
// axis: half the widest spacing a block accepts (ReuseOptions::max_magnification 1.5), so that where the eye came
// closer and the traced points land more than a pixel apart the nearest of them is found (within half a pixel, 4.5 %
// of User1's blocks found none and were traced).
constexpr float kMaxMiss = 0.75f;

// The depth of pixel i's surface along the view axis (0 without a surface).
inline float pixel_depth(const ReuseFrame& frame, size_t i) {
  if (frame.mesh[i] == kNoReuseSurface) return 0.0f;
  return glm::dot(frame.projection.w, frame.position[i] - frame.projection.eye);
}

}  // namespace

ReuseMotion reuse_motion(const ReuseFrame& frame, const ReuseProjection& now) {
  const Tangents& t = frame.camera.tangents;
  const float corner = static_cast<float>(std::sqrt(std::max(t.left * t.left, t.right * t.right) +
                                                    std::max(t.up * t.up, t.down * t.down) + 1.0));
  ReuseMotion m;
  m.shift = glm::length(now.eye - frame.projection.eye);
  m.scale = std::max(now.focal, frame.projection.focal) * corner * m.shift;
  return m;
}

namespace {

// The traced pixel (ix, iy) whose surface point lands within kMaxMiss of `target` in `now` (p: where it lands):
// start at the guess, move by the miss (1 new pixel ~ 1 traced pixel for the small moves between frames).
bool find_traced_pixel(const ReuseFrame& frame, const ReuseProjection& now, const glm::vec2& target, glm::vec2& guess,
                       int& ix, int& iy, glm::vec2& p) {
  const int W = static_cast<int>(frame.camera.extent.width), H = static_cast<int>(frame.camera.extent.height);
  glm::vec2 u = guess;
  float depth = 0.0f;
  for (int it = 0; it < kGatherIterations; ++it) {
    if (!(u.x >= 0.0f && u.y >= 0.0f && u.x < static_cast<float>(W) && u.y < static_cast<float>(H))) return false;
    ix = static_cast<int>(u.x);
    iy = static_cast<int>(u.y);
    const size_t i = static_cast<size_t>(iy) * static_cast<size_t>(W) + static_cast<size_t>(ix);
    if (frame.mesh[i] == kNoReuseSurface || !now.project(frame.position[i], p, depth)) return false;
    const glm::vec2 miss = target - p;
    u = glm::vec2(static_cast<float>(ix) + 0.5f, static_cast<float>(iy) + 0.5f) + miss;
    if (std::fabs(miss.x) <= kMaxMiss && std::fabs(miss.y) <= kMaxMiss) {
      guess = u;
      return true;
    }
  }
  return false;
}

// Whether traced pixel (x, y) is clear of every discontinuity by `pixels` plus how far anything in front of it can
// slide over it (ReuseFrame::near and reuse_motion), and of each side of the image by `pixels` plus what unseen
// geometry beyond that side (at ReuseMotion::unseen_depth) could move.
bool clear_of_edges(const ReuseFrame& frame, int x, int y, float pixels, const ReuseMotion& motion) {
  const float depth = pixel_depth(frame, static_cast<size_t>(y) * frame.camera.extent.width + static_cast<size_t>(x));
  const float far_inverse = 1.0f / (std::max(depth, 1e-3f) + motion.shift);
  // A surface at depth `near_depth` moves at most scale / (near_depth - shift) pixels relative to the eye's view of
  // a point at infinity, so relative to this pixel's surface at most scale x (1 / (near - shift) - 1 / (depth +
  // shift)); plus a pixel.
  auto parallax = [&](float near_depth) {
    const float nd = near_depth - motion.shift;
    if (!(nd > 1e-4f)) return std::numeric_limits<float>::max();
    return motion.scale * std::max(0.0f, 1.0f / nd - far_inverse) + 1.0f;
  };
  // Each side of the image against what lies beyond it (a point beyond one side of the frame's frustum was at
  // least this far from the pixel in the frame's image).
  const int W = static_cast<int>(frame.camera.extent.width), H = static_cast<int>(frame.camera.extent.height);
  int border[4];
  border[kReuseLeft] = x;
  border[kReuseRight] = W - 1 - x;
  border[kReuseTop] = y;
  border[kReuseBottom] = H - 1 - y;
  for (uint32_t side = 0; side < 4; ++side)
    if (!(static_cast<float>(border[side]) >= pixels + parallax(motion.unseen_depth[side]))) return false;
  // Contours form only where the frame saw a surface nearly edge-on while no view direction turned further.
  if (!(motion.shift < kReuseGrazing * (frame.nearest_surface - motion.shift))) return false;
  float within = 0.0f;  // pixels: what lies beyond one radius must not reach the one below
  for (uint32_t k = 0; k < kNearLevels; ++k) {
    const uint32_t r = kNearRadius[k];
    const uint32_t at = (static_cast<uint32_t>(y) / r) * frame.near_x[k] + static_cast<uint32_t>(x) / r;
    const float p = parallax(frame.near[k][at]);
    if (!(p <= (k == 0 ? static_cast<float>(r) : static_cast<float>(kNearRadius[k - 1]) - pixels))) return false;
    if (k == 0) within = p;
  }
  if (!(parallax(frame.nearest) <= static_cast<float>(kNearRadius[kNearLevels - 1]) - pixels)) return false;
  const uint32_t cell = (static_cast<uint32_t>(y) / kReuseCell) * frame.cells_x + static_cast<uint32_t>(x) / kReuseCell;
  return (static_cast<float>(frame.edge_distance[cell]) - 1.0f) * kReuseCell >= pixels + within;
}

}  // namespace

bool reuse_gather_block(const ReuseFrame& frame, const ReuseProjection& now, uint32_t bx, uint32_t by,
                        const ReuseMotion& motion, const ReuseOptions& options, glm::vec2& guess, size_t& out_pixel) {
  const int W = static_cast<int>(frame.camera.extent.width), H = static_cast<int>(frame.camera.extent.height);
  const glm::vec2 target(static_cast<float>(bx) + 2.0f, static_cast<float>(by) + 2.0f);
  int ix = 0, iy = 0;
  glm::vec2 p;
  if (!find_traced_pixel(frame, now, target, guess, ix, iy, p)) return false;
  if (ix + 1 >= W || iy + 1 >= H) return false;
  // The block's pixels lie within 2 new pixels of its centre, so within 2 + kMaxMiss of p: within `reach` traced
  // pixels of (ix, iy) when those are at least kMinBlockSpacing new pixels apart (and no sparser than
  // max_magnification).
  const float reach = std::ceil((2.0f + kMaxMiss) / kMinBlockSpacing);
  if (!clear_of_edges(frame, ix, iy, reach + 2.0f, motion)) return false;
  const size_t i = static_cast<size_t>(iy) * W + ix;
  glm::vec2 px, py;
  float depth = 0.0f;
  if (!now.project(frame.position[i + 1], px, depth) || !now.project(frame.position[i + W], py, depth)) return false;
  const float limit = options.max_magnification * options.max_magnification;
  const float least = kMinBlockSpacing * kMinBlockSpacing;
  if (!(glm::dot(px - p, px - p) <= limit && glm::dot(py - p, py - p) <= limit)) return false;
  // Nor denser (the traced pixels would cover less than the block), nor turned (the block's rows along theirs).
  if (!(std::fabs(px.x - p.x) >= kMinBlockSpacing && std::fabs(py.y - p.y) >= kMinBlockSpacing) ||
      !(glm::dot(px - p, px - p) >= least && glm::dot(py - p, py - p) >= least))
    return false;
  // Every cell the block's pixels can come from: uniform, the same as (ix, iy)'s.
  const int r = static_cast<int>(std::ceil(reach));
  const uint32_t cx0 = static_cast<uint32_t>(std::max(0, ix - r)) / kReuseCell;
  const uint32_t cx1 = static_cast<uint32_t>(std::min(W - 1, ix + r)) / kReuseCell;
  const uint32_t cy0 = static_cast<uint32_t>(std::max(0, iy - r)) / kReuseCell;
  const uint32_t cy1 = static_cast<uint32_t>(std::min(H - 1, iy + r)) / kReuseCell;
  const size_t first = (static_cast<size_t>(iy) / kReuseCell) * frame.cells_x + static_cast<size_t>(ix) / kReuseCell;
  const uint32_t mesh = frame.cell_mesh[first];
  if (mesh == kNoReuseSurface) return false;
  for (uint32_t cy = cy0; cy <= cy1; ++cy)
    for (uint32_t cx = cx0; cx <= cx1; ++cx) {
      const size_t c = static_cast<size_t>(cy) * frame.cells_x + cx;
      if (frame.cell_mesh[c] != mesh) return false;
      // Uniform cells are compared by their first pixels.
      const size_t a = static_cast<size_t>(cy) * kReuseCell * W + cx * kReuseCell;
      if (frame.mask[a] != frame.mask[i] || frame.known[a] != frame.known[i] || frame.reached[a] != frame.reached[i])
        return false;
    }
  out_pixel = i;
  return true;
}

namespace {

// What finish_reuse_cells learns of a pixel and its right or lower neighbour (one byte per pixel: the right pair's
// flags, then the lower pair's shifted by kLowerPair).
enum : uint8_t {
  kPairEdge = 1,    // a discontinuity as the edge distances see it: surface against none, another mesh, or the
                    // neighbour off this pixel's tangent plane
  kPairBreak = 2,   // either one occludes: another mesh or none, or either off the other's tangent plane
  kPairCurved = 4,  // their normals differ (dot below kReuseFlat)
};
constexpr uint32_t kLowerPair = 3;

// The flags of pixels i and j (j right of or below i), whose depths are depth_i and depth_j. Symmetric but for
// kPairEdge, which is i's view.
uint8_t pair_flags(const ReuseFrame& frame, size_t i, size_t j, float depth_i, float depth_j,
                   const ReuseOptions& options) {
  const bool surface = frame.mesh[i] != kNoReuseSurface, other = frame.mesh[j] != kNoReuseSurface;
  if (surface != other) return kPairEdge | kPairBreak;
  if (!surface) return 0;
  if (frame.mesh[j] != frame.mesh[i]) return kPairEdge | kPairBreak;
  const float tolerance_i = options.plane_tolerance * depth_i / frame.projection.focal;
  const float tolerance_j = options.plane_tolerance * depth_j / frame.projection.focal;
  const glm::vec3 d = frame.position[j] - frame.position[i];
  uint8_t flags = 0;
  if (!(std::fabs(glm::dot(d, frame.normal[i])) <= tolerance_i))
    flags = kPairEdge | kPairBreak;
  else if (!(std::fabs(glm::dot(d, frame.normal[j])) <= tolerance_j))
    flags = kPairBreak;
  if (!(glm::dot(frame.normal[i], frame.normal[j]) >= kReuseFlat)) flags |= kPairCurved;
  return flags;
}

}  // namespace

void finish_reuse_cells(ReuseFrame& frame, uint32_t cell_y0, uint32_t cell_y1, const ReuseOptions& options) {
  const uint32_t W = frame.camera.extent.width, H = frame.camera.extent.height;
  const uint32_t y0 = cell_y0 * kReuseCell, y1 = std::min(H, cell_y1 * kReuseCell);
  if (y0 >= y1) return;
  // Each pixel's depth is found once and each pair of neighbours looked at once: rows [y0 - 1, y1) of pair flags
  // (the row above for the first row's upper pairs), depths of rows [y0 - 1, y1 + 1).
  const uint32_t top = y0 > 0 ? y0 - 1 : y0, bottom = std::min(H, y1 + 1);
  thread_local std::vector<uint8_t> pair_scratch;
  thread_local std::vector<float> depth_scratch;
  pair_scratch.resize(static_cast<size_t>(y1 - top) * W);  // every entry is written below
  depth_scratch.resize(static_cast<size_t>(bottom - top) * W);
  uint8_t* const pairs = pair_scratch.data();
  float* const depths = depth_scratch.data();
  const size_t offset = static_cast<size_t>(top) * W;  // pixel index of pairs[0] and depths[0]
  for (size_t i = offset; i < static_cast<size_t>(bottom) * W; ++i) depths[i - offset] = pixel_depth(frame, i);
  for (uint32_t y = top; y < y1; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      const size_t i = static_cast<size_t>(y) * W + x, at = i - offset;
      uint8_t f = 0;
      if (x + 1 < W) f = pair_flags(frame, i, i + 1, depths[at], depths[at + 1], options);
      if (y + 1 < H)
        f = static_cast<uint8_t>(f | pair_flags(frame, i, i + W, depths[at], depths[at + W], options) << kLowerPair);
      pairs[at] = f;
    }
  constexpr uint8_t kEdges = kPairEdge | kPairEdge << kLowerPair;
  for (uint32_t cy = cell_y0; cy < cell_y1; ++cy)
    for (uint32_t cx = 0; cx < frame.cells_x; ++cx) {
      float nearest = std::numeric_limits<float>::max(), occluding = nearest;
      const size_t cell = static_cast<size_t>(cy) * frame.cells_x + cx;
      const size_t first = static_cast<size_t>(cy) * kReuseCell * W + cx * kReuseCell;
      bool edge = false, uniform = frame.mesh[first] != kNoReuseSurface;
      for (uint32_t y = cy * kReuseCell; y < std::min(H, (cy + 1) * kReuseCell); ++y)
        for (uint32_t x = cx * kReuseCell; x < std::min(W, (cx + 1) * kReuseCell); ++x) {
          const size_t i = static_cast<size_t>(y) * W + x;
          const size_t at = i - offset;
          uniform = uniform && frame.mesh[i] == frame.mesh[first] && frame.mask[i] == frame.mask[first] &&
                    frame.known[i] == frame.known[first] && frame.reached[i] == frame.reached[first];
          edge = edge || (pairs[at] & kEdges) != 0;
          if (frame.mesh[i] == kNoReuseSurface) continue;
          const float depth = depths[at];
          nearest = std::min(nearest, depth);
          if (!(occluding > depth)) continue;
          // A surface pixel occludes on either side of a discontinuity with any of its four neighbours (off either
          // one's tangent plane: both sides find it), and where a contour may form: seen nearly edge-on, with a
          // neighbour of another normal (a plane seen edge-on hides nothing; its edges are discontinuities).
          uint8_t around = static_cast<uint8_t>((pairs[at] | pairs[at] >> kLowerPair) & (kPairBreak | kPairCurved));
          if (x > 0) around |= pairs[at - 1] & (kPairBreak | kPairCurved);
          if (y > top) around |= (pairs[at - W] >> kLowerPair) & (kPairBreak | kPairCurved);
          bool occludes = (around & kPairBreak) != 0;
          if (!occludes && (around & kPairCurved)) {
            const glm::vec3 to_eye = frame.projection.eye - frame.position[i];
            occludes = !(std::fabs(glm::dot(frame.normal[i], to_eye)) > kReuseGrazing * glm::length(to_eye));
          }
          if (occludes) occluding = depth;
        }
      if (edge) frame.edge_distance[cell] = 0;
      frame.cell_mesh[cell] = uniform ? frame.mesh[first] : kNoReuseSurface;
      frame.cell_depth[cell] = occluding;
      frame.cell_surface_depth[cell] = nearest;
    }
}

void finish_reuse_distances(ReuseFrame& frame) {
  // Two-pass chamfer transform with unit steps to all eight neighbours (Chebyshev distance), capped at 255.
  const int cx = static_cast<int>(frame.cells_x), cy = static_cast<int>(frame.cells_y);
  std::vector<uint8_t>& d = frame.edge_distance;
  auto at = [&](int x, int y) -> uint8_t& { return d[static_cast<size_t>(y) * cx + x]; };
  // Near depths: per level, the minimum of the cell depths in each cell of kNearRadius[k] pixels, then over its 3x3
  // neighbourhood (which covers at least the radius around any point of the centre cell).
  frame.nearest = std::numeric_limits<float>::max();
  for (float v : frame.cell_depth) frame.nearest = std::min(frame.nearest, v);
  frame.nearest_surface = std::numeric_limits<float>::max();
  for (float v : frame.cell_surface_depth) frame.nearest_surface = std::min(frame.nearest_surface, v);
  // A level whose cells are whole multiples of a finer level's is pooled from that level's (min is exact: the same
  // values as from the cells themselves).
  std::vector<float> pooled[kNearLevels];
  int pooled_x[kNearLevels] = {}, pooled_y[kNearLevels] = {};
  for (uint32_t k = 0; k < kNearLevels; ++k) {
    const int per = static_cast<int>(kNearRadius[k] / kReuseCell);
    const std::vector<float>* src = &frame.cell_depth;
    int sw = cx, sh = cy, f = per;
    for (uint32_t j = 0; j < k; ++j) {
      const int per_j = static_cast<int>(kNearRadius[j] / kReuseCell);
      if (per % per_j == 0 && per / per_j < f) {
        src = &pooled[j];
        sw = pooled_x[j];
        sh = pooled_y[j];
        f = per / per_j;
      }
    }
    const int nx = (sw + f - 1) / f, ny = (sh + f - 1) / f;
    std::vector<float>& pool = pooled[k];
    pool.assign(static_cast<size_t>(nx) * ny, std::numeric_limits<float>::max());
    for (int sy = 0, py = 0, in_row = 0; sy < sh; ++sy) {
      const float* from = src->data() + static_cast<size_t>(sy) * sw;
      float* to = pool.data() + static_cast<size_t>(py) * nx;
      for (int px = 0; px < nx; ++px)
        for (int sx = px * f; sx < std::min(sw, (px + 1) * f); ++sx) to[px] = std::min(to[px], from[sx]);
      if (++in_row == f) {
        in_row = 0;
        ++py;
      }
    }
    pooled_x[k] = nx;
    pooled_y[k] = ny;
    // The minimum over each pooled cell's 3x3 neighbourhood: along rows, then along columns.
    std::vector<float> across(pool.size());
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const size_t i = static_cast<size_t>(y) * nx + x;
        float m = pool[i];
        if (x > 0) m = std::min(m, pool[i - 1]);
        if (x + 1 < nx) m = std::min(m, pool[i + 1]);
        across[i] = m;
      }
    std::vector<float>& near = frame.near[k];
    near.resize(pool.size());
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const size_t i = static_cast<size_t>(y) * nx + x;
        float m = across[i];
        if (y > 0) m = std::min(m, across[i - nx]);
        if (y + 1 < ny) m = std::min(m, across[i + nx]);
        near[i] = m;
      }
    frame.near_x[k] = static_cast<uint32_t>(nx);
  }
  for (int y = 0; y < cy; ++y)
    for (int x = 0; x < cx; ++x) {
      int v = at(x, y);
      if (x > 0) v = std::min(v, at(x - 1, y) + 1);
      if (y > 0) {
        v = std::min(v, at(x, y - 1) + 1);
        if (x > 0) v = std::min(v, at(x - 1, y - 1) + 1);
        if (x + 1 < cx) v = std::min(v, at(x + 1, y - 1) + 1);
      }
      at(x, y) = static_cast<uint8_t>(v);
    }
  for (int y = cy - 1; y >= 0; --y)
    for (int x = cx - 1; x >= 0; --x) {
      int v = at(x, y);
      if (x + 1 < cx) v = std::min(v, at(x + 1, y) + 1);
      if (y + 1 < cy) {
        v = std::min(v, at(x, y + 1) + 1);
        if (x + 1 < cx) v = std::min(v, at(x + 1, y + 1) + 1);
        if (x > 0) v = std::min(v, at(x - 1, y + 1) + 1);
      }
      at(x, y) = static_cast<uint8_t>(v);
    }
}

}  // namespace dhr::server
