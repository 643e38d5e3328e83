#include "trace/reuse/reuse_frame.hpp"
#include "visibility/soft_levels.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace dhr::server {
namespace {

// Normals of neighbours on one smooth surface agree to within about 25 degrees (tessellated furniture); a crease
// or a corner between two walls does not, and a contact shadow lives there.
constexpr float kMinNormalCos = 0.9f;

}  // namespace

ReuseProjection ReuseProjection::of(const Camera& camera, const glm::vec3& eye) {
  const glm::dmat3 R = glm::mat3_cast(glm::normalize(camera.T_world_eye.orientation));
  const Tangents& t = camera.tangents;
  const double W = camera.extent.width, H = camera.extent.height;
  // px = (tx - left) / width * W, py = (up - ty) / height * H, with tx = c.x / w, ty = c.y / w, c = R^T d and
  // w = -c.z: each is (a c + b w) / w, so one row per coordinate dotted with d.
  const double axs = W / t.width(), bx = -t.left * axs;
  const double ays = -H / t.height(), by = t.up * H / t.height();
  ReuseProjection p;
  p.eye = eye;
  p.w = glm::vec3(-R[2]);
  p.ax = glm::vec3(R[0] * axs - R[2] * bx);
  p.ay = glm::vec3(R[1] * ays - R[2] * by);
  p.focal = static_cast<float>(std::min(camera.focal_x(), camera.focal_y()));
  return p;
}

bool ReuseProjection::project(const glm::vec3& x, glm::vec2& out_pixel, float& out_depth) const {
  const glm::vec3 d = x - eye;
  out_depth = glm::dot(w, d);
  if (!(out_depth > 1e-6f)) return false;
  out_pixel = glm::vec2(glm::dot(ax, d), glm::dot(ay, d)) / out_depth;
  return true;
}

void ReuseFrame::reset(const Camera& cam, const glm::vec3& eye, uint32_t light_count, uint32_t bits, double time,
                       uint32_t gen) {
  camera = cam;
  projection = ReuseProjection::of(cam, eye);
  lights = light_count;
  mask_bits = bits;
  scene_time = time;
  generation = gen;
  const size_t pixels = static_cast<size_t>(cam.extent.width) * cam.extent.height;
  // The tracer writes every pixel (kNoReuseSurface where nothing may be reused): no fill needed here.
  position.resize(pixels);
  normal.resize(pixels);
  shading.resize(pixels);
  mesh.resize(pixels);
  mask.resize(pixels);
  known.resize(pixels);
  reached.resize(pixels);
  cells_x = (cam.extent.width + kReuseCell - 1) / kReuseCell;
  cells_y = (cam.extent.height + kReuseCell - 1) / kReuseCell;
  edge_distance.clear();
  cell_mesh.resize(static_cast<size_t>(cells_x) * cells_y);
  cell_depth.resize(static_cast<size_t>(cells_x) * cells_y);
  cell_surface_depth.resize(static_cast<size_t>(cells_x) * cells_y);
  light_state.clear();
  moving_boxes.clear();
  region.clear();  // the tracer sizes it when its scene has light slots
}

bool reuse_same_surface(const glm::vec3& pa, const glm::vec3& na, const glm::vec3& pb, const glm::vec3& nb,
                        float spacing, const ReuseOptions& options) {
  if (!(glm::dot(na, nb) >= kMinNormalCos)) return false;
  const glm::vec3 d = pb - pa;
  const float reach = options.neighbour_reach * spacing, tolerance = options.plane_tolerance * spacing;
  return glm::dot(d, d) <= reach * reach && std::fabs(glm::dot(d, na)) <= tolerance &&
         std::fabs(glm::dot(d, nb)) <= tolerance;
}

bool reuse_corners(const ReuseFrame& frame, const ReuseQuery& query, const ReuseOptions& options,
                   ReuseCorners& out) {
  if (!frame.valid()) return false;
  glm::vec2 pixel;
  float depth = 0.0f;
  if (!frame.projection.project(query.position, pixel, depth)) return false;
  // Metres between neighbouring pixels of the source at X, across its view axis.
  const float spacing = depth / frame.projection.focal;
  if (!(spacing <= options.max_magnification * query.spacing)) return false;
  // The 2x2 traced pixels whose centres surround the projected point.
  const float fx = std::floor(pixel.x - 0.5f), fy = std::floor(pixel.y - 0.5f);
  const uint32_t width = frame.camera.extent.width, height = frame.camera.extent.height;
  if (!(fx >= 0.0f && fy >= 0.0f && fx + 1.0f < static_cast<float>(width) && fy + 1.0f < static_cast<float>(height)))
    return false;
  const size_t x0 = static_cast<size_t>(fx), y0 = static_cast<size_t>(fy);
  out.index[0] = y0 * width + x0;
  out.index[1] = out.index[0] + 1;
  out.index[2] = out.index[0] + width;
  out.index[3] = out.index[2] + 1;
  for (const size_t i : out.index) {
    if (frame.mesh[i] != query.mesh) return false;
    if (!frame.region.empty() && frame.region[i] != query.region) return false;
    if (!reuse_same_surface(query.position, query.normal, frame.position[i], frame.normal[i], spacing, options))
      return false;
  }
  const float ax = pixel.x - 0.5f - fx, ay = pixel.y - 0.5f - fy;
  out.weight[0] = (1.0f - ax) * (1.0f - ay);
  out.weight[1] = ax * (1.0f - ay);
  out.weight[2] = (1.0f - ax) * ay;
  out.weight[3] = ax * ay;
  return true;
}

ReuseAnswer reuse_lookup(const ReuseFrame& frame, const ReuseQuery& query, uint32_t candidates,
                         const ReuseOptions& options) {
  ReuseCorners corners;
  if (!reuse_corners(frame, query, options, corners)) return {};
  return reuse_answer(frame, corners, candidates);
}

ReuseAnswer reuse_answer(const ReuseFrame& frame, const ReuseCorners& corners, uint32_t candidates) {
  uint32_t known = candidates, all_reached = 0xFFFFFFFFu, any_reached = 0u, all_mask = 0xFFFFFFFFu, any_mask = 0u;
  for (const size_t i : corners.index) {
    known &= frame.known[i];
    all_reached &= frame.reached[i];
    any_reached |= frame.reached[i];
    all_mask &= frame.mask[i];
    any_mask |= frame.mask[i];
  }
  known &= ~(all_reached ^ any_reached);  // the four agree
  return {known, all_reached & known, ~(all_mask ^ any_mask), all_mask};
}

SoftHistory reuse_soft_history(const ReuseFrame& frame, const ReuseCorners& corners, uint32_t slot) {
  if (frame.tally.empty() || slot >= frame.tally_stride) return {};
  // Weighted by position and by samples: a corner with more samples knows its share better.
  float visible = 0.0f, samples = 0.0f, weight = 0.0f, lo = 1.0f, hi = 0.0f;
  for (int k = 0; k < 4; ++k) {
    const SoftTally& t = frame.tally[corners.index[k] * frame.tally_stride + slot];
    if (t.samples == 0) return {};  // a corner without a tally: no history (a fresh trace there)
    if (corners.weight[k] > kSoftHistoryWeightFloor) {  // a corner that takes part in the blend
      lo = std::min(lo, tally_fraction(t));
      hi = std::max(hi, tally_fraction(t));
      if (hi - lo > kSoftHistorySpread) return {};
    }
    visible += corners.weight[k] * tally_fraction(t) * static_cast<float>(t.samples);
    samples += corners.weight[k] * static_cast<float>(t.samples);
    weight += corners.weight[k];
  }
  if (!(weight > 0.0f) || !(samples > 0.0f)) return {};
  return {visible / samples, samples / weight};
}

float soft_level_hysteresis(float fraction, float history_fraction, float hysteresis) {
  if (!(hysteresis > 0.0f)) return fraction;
  const float top = static_cast<float>(kDefaultSoftLevels - 1);
  const float held = static_cast<float>(quantize(history_fraction, kDefaultSoftLevels));
  return std::fabs(fraction * top - held) <= 0.5f + hysteresis ? held / top : fraction;
}

SoftTally add_soft_samples(const SoftHistory& history, uint32_t visible, uint32_t samples, uint32_t cap) {
  const float n_new = static_cast<float>(samples);
  const float n_old = std::max(0.0f, std::min(history.samples, static_cast<float>(cap) - n_new));
  const float n = n_old + n_new;
  if (!(n > 0.0f)) return {};
  const float share = (history.fraction * n_old + static_cast<float>(visible)) / n;
  SoftTally t;
  t.share = static_cast<uint16_t>(std::lround(std::clamp(share, 0.0f, 1.0f) * 65535.0f));
  t.samples = static_cast<uint16_t>(std::min(65535.0f, std::round(n)));
  return t;
}

bool segment_misses_boxes(const glm::vec3& from, const glm::vec3& to, const std::vector<ReuseBox>& boxes,
                          float margin) {
  const glm::vec3 d = to - from;
  for (const ReuseBox& box : boxes) {
    // Slab test of the segment from + s d, s in [0, 1], against the widened box.
    float s0 = 0.0f, s1 = 1.0f;
    bool misses = false;
    for (int a = 0; a < 3 && !misses; ++a) {
      const float lo = box.lo[a] - margin, hi = box.hi[a] + margin;
      if (std::fabs(d[a]) < 1e-20f) {
        misses = from[a] < lo || from[a] > hi;
        continue;
      }
      float t0 = (lo - from[a]) / d[a], t1 = (hi - from[a]) / d[a];
      if (t0 > t1) std::swap(t0, t1);
      s0 = std::max(s0, t0);
      s1 = std::min(s1, t1);
      misses = s0 > s1;
    }
    if (!misses) return false;
  }
  return true;
}

}  // namespace dhr::server
