#include "trace/reuse/reuse_frame.hpp"

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

// The 4x4 ordered-dither matrix: consecutive generations refresh pixels spread over the block.
constexpr uint32_t kBayer4[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};

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
  light_state.clear();
  moving_boxes.clear();
  region.clear();  // the tracer sizes it when its scene has light slots
}

bool reuse_refresh_pixel(uint32_t x, uint32_t y, uint32_t generation) {
  return kBayer4[(y & 3u) * 4u + (x & 3u)] == generation % kRefreshPeriod;
}

bool reuse_same_surface(const glm::vec3& pa, const glm::vec3& na, const glm::vec3& pb, const glm::vec3& nb,
                        float spacing, const ReuseOptions& options) {
  if (!(glm::dot(na, nb) >= kMinNormalCos)) return false;
  const glm::vec3 d = pb - pa;
  const float reach = options.neighbour_reach * spacing, tolerance = options.plane_tolerance * spacing;
  return glm::dot(d, d) <= reach * reach && std::fabs(glm::dot(d, na)) <= tolerance &&
         std::fabs(glm::dot(d, nb)) <= tolerance;
}

ReuseAnswer reuse_lookup(const ReuseFrame& frame, const ReuseQuery& query, uint32_t candidates,
                         const ReuseOptions& options) {
  if (!frame.valid()) return {};
  glm::vec2 pixel;
  float depth = 0.0f;
  if (!frame.projection.project(query.position, pixel, depth)) return {};
  // Metres between neighbouring pixels of the source at X, across its view axis.
  const float spacing = depth / frame.projection.focal;
  if (!(spacing <= options.max_magnification * query.spacing)) return {};
  // The 2x2 traced pixels whose centres surround the projected point.
  const float fx = std::floor(pixel.x - 0.5f), fy = std::floor(pixel.y - 0.5f);
  const uint32_t width = frame.camera.extent.width, height = frame.camera.extent.height;
  if (!(fx >= 0.0f && fy >= 0.0f && fx + 1.0f < static_cast<float>(width) && fy + 1.0f < static_cast<float>(height)))
    return {};
  const size_t x0 = static_cast<size_t>(fx), y0 = static_cast<size_t>(fy);
  const size_t corners[4] = {y0 * width + x0, y0 * width + x0 + 1, (y0 + 1) * width + x0, (y0 + 1) * width + x0 + 1};

  uint32_t known = candidates, all_reached = 0xFFFFFFFFu, any_reached = 0u, all_mask = 0xFFFFFFFFu, any_mask = 0u;
  for (const size_t i : corners) {
    if (frame.mesh[i] != query.mesh) return {};
    if (!frame.region.empty() && frame.region[i] != query.region) return {};
    if (!reuse_same_surface(query.position, query.normal, frame.position[i], frame.normal[i], spacing, options))
      return {};
    known &= frame.known[i];
    all_reached &= frame.reached[i];
    any_reached |= frame.reached[i];
    all_mask &= frame.mask[i];
    any_mask |= frame.mask[i];
  }
  known &= ~(all_reached ^ any_reached);  // the four agree
  return {known, all_reached & known, ~(all_mask ^ any_mask), all_mask};
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
