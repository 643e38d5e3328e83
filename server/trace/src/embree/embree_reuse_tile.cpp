// The Embree tile kernel's reuse steps (trace/reuse/reuse_frame.hpp): whole pixels from the eye's previous trace,
// pairs from any source, and what a traced tile leaves in the record.
#include "trace/embree/embree_trace_tile.hpp"

#include "trace/embree/tile_pool.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace dhr::server::detail {
namespace {

// A directional light's shadow segment is tested this far toward the light (metres): past any scene's boxes.
constexpr float kDirectionalReach = 1.0e5f;

glm::vec3 segment_end(const PackedLight& light, const glm::vec3& from) {
  if (light_eval::light_is_directional(light)) return from - glm::vec3(light.direction_range) * kDirectionalReach;
  return glm::vec3(light.position_type);
}

ReuseBox box_of(const EmbreeMesh& mesh) {
  ReuseBox box{glm::vec3(std::numeric_limits<float>::max()), glm::vec3(-std::numeric_limits<float>::max())};
  // positions ends with Embree's padding element.
  const size_t n = mesh.positions.empty() ? 0 : mesh.positions.size() - 1;
  for (size_t i = 0; i < n; ++i) {
    box.lo = glm::min(box.lo, mesh.positions[i]);
    box.hi = glm::max(box.hi, mesh.positions[i]);
  }
  return box;
}

// The light-slot cell of a surface point (relative frame): ReuseFrame::region.
uint32_t region_of(const FrameSetup& frame, const glm::vec3& position) {
  return frame.slots->cell_of(glm::dvec3(position) + frame.scene->origin());
}

// Whether the shadow segments from `at` toward the lights in `lights` miss what moves (now, and in `source`).
uint32_t lights_clear_of_motion(const FrameSetup& frame, const ReuseFrame& source, const glm::vec3& at,
                                uint32_t lights, float margin) {
  const ReuseSetup& reuse = *frame.reuse;
  for (uint32_t li = 0; li < 32; ++li) {
    const uint32_t bit = 1u << li;
    if (!(lights & bit)) continue;
    const glm::vec3 end = segment_end(frame.lights[li], at);
    if (!segment_misses_boxes(at, end, reuse.moving_boxes, margin) ||
        !segment_misses_boxes(at, end, source.moving_boxes, margin))
      lights &= ~bit;
  }
  return lights;
}

}  // namespace

namespace {

// How far the point query looks for the nearest geometry (metres): beyond it, unseen geometry is treated as that far.
constexpr float kUnseenSearch = 10.0f;

// The length of the frustum's corner ray at unit depth: a point inside it at distance r has depth >= r / this.
float frustum_corner(const Camera& camera) {
  const Tangents& t = camera.tangents;
  return static_cast<float>(
      std::sqrt(std::max(t.left * t.left, t.right * t.right) + std::max(t.up * t.up, t.down * t.down) + 1.0));
}

// The region `frame` sees: its frustum's four sides through the eye and its near plane (dot((x, 1)) >= 0 inside).
std::vector<glm::vec4> frustum_now(const FrameSetup& frame) {
  const Tangents& t = frame.camera->tangents;
  const glm::dmat3 R = frame.world_from_eye;
  auto through_eye = [&](const glm::dvec3& n) {
    const glm::vec3 nf(n);
    return glm::vec4(nf, -glm::dot(nf, frame.eye));
  };
  // x = eye + d, c = R^T d, w = -c.z: tx = c.x / w between left and right, ty = c.y / w between down and up.
  const glm::vec3 w(frame.ray_forward);
  return {through_eye(R[0] + t.left * R[2]), through_eye(-R[0] - t.right * R[2]), through_eye(-R[1] - t.up * R[2]),
          through_eye(R[1] + t.down * R[2]),
          glm::vec4(w, -glm::dot(w, frame.eye) - static_cast<float>(frame.primary_near))};
}

// Whether some triangle lies beyond `frame`'s near plane inside its frustum but was nearer than the near plane in
// `previous`. Such a point has depth_now < (near + eye move) / (1 - turn x corner) (turn: the angle between the view
// axes, corner: the frustum's corner ray length at unit depth), which bounds the point query; a turn that large
// (turn x corner >= 1/2) counts as crossing.
bool near_plane_crossing(const EmbreeScene& scene, const FrameSetup& frame, const ReuseFrame& previous) {
  const float corner = frustum_corner(*frame.camera);
  const glm::vec3 w_now = glm::vec3(frame.ray_forward), w_then = previous.projection.w;
  const float turn = std::acos(std::clamp(glm::dot(w_now, w_then), -1.0f, 1.0f));
  if (!(turn * corner < 0.5f)) return true;
  const float near = static_cast<float>(frame.primary_near);
  const glm::vec3 eye_then = previous.projection.eye;
  const float moved = glm::length(frame.eye - eye_then);
  const float radius = corner * (near + moved) / (1.0f - turn * corner);
  // Beyond the near plane now, inside this frustum, at or nearer than the near plane then.
  std::vector<glm::vec4> planes = frustum_now(frame);
  planes.push_back(glm::vec4(-w_then, glm::dot(w_then, eye_then) + near));
  return scene.geometry_within(frame.eye, radius, planes);
}

// Per side of `previous`'s image (ReuseSide), the distance from either eye to the nearest geometry that this
// frame sees (frustum_now) and that lies beyond that side of `previous`'s frustum (outside the plane through its
// eye and that side's corner rays), at most kUnseenSearch. Only such geometry enters this image from beyond that
// side: what `previous` saw is in its pixels, what lay nearer than its near plane is near_plane_crossing's.
std::array<float, 4> unseen_distances(const EmbreeScene& scene, const FrameSetup& frame,
                                      const ReuseFrame& previous) {
  const glm::vec3 eyes[2] = {frame.eye, previous.projection.eye};
  std::vector<glm::vec4> region = frustum_now(frame);
  region.emplace_back();
  const Camera& cam = previous.camera;
  const double W = cam.extent.width, H = cam.extent.height;
  const glm::dvec3 centre = cam.world_ray(W / 2.0, H / 2.0);
  glm::dvec2 corners[4][2];  // each side's two corners, in pixels
  corners[kReuseLeft][0] = {0, 0};
  corners[kReuseLeft][1] = {0, H};
  corners[kReuseRight][0] = {W, 0};
  corners[kReuseRight][1] = {W, H};
  corners[kReuseTop][0] = {0, 0};
  corners[kReuseTop][1] = {W, 0};
  corners[kReuseBottom][0] = {0, H};
  corners[kReuseBottom][1] = {W, H};
  std::array<float, 4> out{};
  for (uint32_t side = 0; side < 4; ++side) {
    glm::dvec3 n = glm::normalize(glm::cross(cam.world_ray(corners[side][0].x, corners[side][0].y),
                                             cam.world_ray(corners[side][1].x, corners[side][1].y)));
    if (glm::dot(n, centre) > 0.0) n = -n;  // toward the outside of the frustum
    const glm::vec3 nf(n);
    region.back() = glm::vec4(nf, -glm::dot(nf, eyes[1]));
    float d = kUnseenSearch;
    for (const glm::vec3& eye : eyes) d = std::min(d, scene.nearest_distance(eye, d, region));
    out[side] = d;
  }
  return out;
}

}  // namespace

ReuseSetup make_reuse_setup(const EmbreeScene& scene, const FrameSetup& frame, const ReuseRequest& request,
                            const VisibilityLayout& layout, double scene_time) {
  const uint32_t lights = layout.light_count, mask_bits = layout.total_bits();
  uint32_t hard_lights = 0;
  for (uint32_t li = 0; li < lights; ++li)
    if (!layout.is_soft(li)) hard_lights |= 1u << li;
  ReuseSetup setup;
  setup.history_slot.fill(0xFF);
  for (uint32_t li = 0; li < lights; ++li) setup.field_bits[li] = ((1u << layout.bits[li]) - 1u) << layout.offset[li];
  uint32_t soft_unmoved = ~hard_lights & (lights >= 32 ? 0xFFFFFFFFu : (1u << lights) - 1u);
  setup.options = request.options;
  setup.record = request.record;
  setup.now = ReuseProjection::of(*frame.camera, frame.eye);
  // A record that is also a source would be overwritten while read: it is not one.
  const ReuseFrame* previous =
      request.previous && request.previous != request.record && request.previous->valid() ? request.previous : nullptr;
  setup.generation = previous ? previous->generation + 1 : 0;
  setup.moving_mesh.assign(scene.meshes().size(), 0);
  for (uint32_t m : scene.moving_meshes()) {
    setup.moving_mesh[m] = 1;
    setup.moving_boxes.push_back(box_of(scene.meshes()[m]));
  }
  setup.motion = !setup.moving_boxes.empty();
  const uint32_t all_lights = lights >= 32 ? 0xFFFFFFFFu : (1u << lights) - 1u;
  // The answers' bits are the layout's fields. Without slots field i is light i; with slots a field holds several
  // lights, and every light's state is recorded (a field whose light moved is not taken). Slots are placed at rest:
  // with slots, nothing is reused while something moves.
  const uint32_t entries = frame.slots ? static_cast<uint32_t>(frame.lights.size()) : lights;

  if (request.options.enabled && !(frame.slots && setup.motion)) {
    std::vector<const ReuseFrame*> candidates;
    if (previous) candidates.push_back(previous);
    for (const ReuseFrame* f : request.shared)
      if (f && f != previous && f->valid()) candidates.push_back(f);
    for (const ReuseFrame* f : candidates) {
      if (f == request.record || f->lights != lights || f->mask_bits != mask_bits ||
          f->light_state.size() != 2u * entries || (frame.slots && !f->moving_boxes.empty()))
        continue;
      uint32_t unmoved = all_lights;
      for (uint32_t li = 0; li < entries; ++li) {
        const PackedLight& now = frame.lights[li];
        if ((f->light_state[2 * li] != now.position_type || f->light_state[2 * li + 1] != now.direction_range) &&
            frame.field[li] < 32)
          unmoved &= ~(1u << frame.field[li]);
      }
      if (f == previous && request.options.whole_pixels) {
        setup.previous = f;
        setup.previous_lights = unmoved;
      }
      if (f == previous && !f->tally.empty() && f->tally.size() == f->mesh.size() * f->tally_stride) {
        setup.history = f;
        setup.history_lights = unmoved & ~hard_lights;
      }
      soft_unmoved &= unmoved;
      if (!request.options.pairs) continue;
      setup.sources.push_back({f, unmoved & hard_lights});
      setup.usable_lights |= unmoved & hard_lights;
      setup.motion = setup.motion || !f->moving_boxes.empty();
    }
    if (!setup.sources.empty() && !setup.motion) setup.soft_lights = soft_unmoved;
    // The previous trace's tallies are of the same layout (checked above): the same slots.
    if (setup.motion || frame.slots || request.options.soft_history == 0 || !request.record) {
      setup.history = nullptr;
      setup.history_lights = 0;
    }
    if (setup.previous) {
      setup.eye_motion = reuse_motion(*setup.previous, setup.now);
      // Primary rays start at the near plane. Geometry that was nearer than it then and is not now appears
      // anywhere in the image: whole pixels only when no triangle meets that region inside this camera's frustum
      // (gather_tile checks the other way: a taken point must lie beyond the near plane now).
      setup.columns.assign(frame.ray_columns.begin(), frame.ray_columns.end());
      setup.rows.assign(frame.ray_rows.begin(), frame.ray_rows.end());
      setup.forward = glm::vec3(frame.ray_forward);
      // Geometry no pixel saw enters from beyond a side of the previous frustum: it is at least as far from the
      // eyes as the nearest triangle beyond that side, so at that depth or deeper (over the corner ray's length).
      const std::array<float, 4> beyond = unseen_distances(scene, frame, *setup.previous);
      for (uint32_t side = 0; side < 4; ++side)
        setup.eye_motion.unseen_depth[side] =
            std::max(setup.eye_motion.unseen_depth[side], beyond[side] / frustum_corner(*frame.camera));
      if (near_plane_crossing(scene, frame, *setup.previous)) {
        setup.previous = nullptr;
        setup.near_geometry = true;
      }
    }
  }

  if (ReuseFrame* rec = request.record) {
    rec->reset(*frame.camera, frame.eye, lights, mask_bits, scene_time, setup.generation);
    if (frame.slots) rec->region.resize(rec->mesh.size());
    for (uint32_t li = 0; li < entries; ++li) {
      rec->light_state.push_back(frame.lights[li].position_type);
      rec->light_state.push_back(frame.lights[li].direction_range);
    }
    rec->moving_boxes = setup.moving_boxes;
    // Tallies where soft samples may accumulate (the record's pixels start without one: gather_tile clears them).
    if (layout.any_soft() && !frame.slots && request.options.enabled && request.options.soft_history > 0) {
      for (uint32_t li = 0; li < lights; ++li)
        if (layout.is_soft(li)) setup.history_slot[li] = static_cast<uint8_t>(setup.history_stride++);
      rec->tally.resize(rec->mesh.size() * setup.history_stride);
    } else {
      rec->tally.clear();
    }
    rec->tally_stride = setup.history_stride;
    rec->edge_distance.assign(static_cast<size_t>(rec->cells_x) * rec->cells_y, 255);
  }
  return setup;
}

void gather_tile(const FrameSetup& frame, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, TileScratch& scratch,
                 VisibilityBuffer& out, TraceStats& stats) {
  scratch.skip.clear();
  scratch.partial_hits.clear();
  scratch.partial_pixels.clear();
  scratch.partial_known.clear();
  scratch.partial_reached.clear();
  const ReuseSetup* reuse = frame.reuse;
  if (!reuse) return;
  ReuseFrame* rec = reuse->record;
  const size_t width = frame.camera->extent.width;
  // The record's pixels start without a surface: gathered and hit pixels get theirs.
  if (rec)
    for (uint32_t y = y0; y < y1; ++y) {
      std::fill_n(rec->mesh.begin() + static_cast<ptrdiff_t>(y * width + x0), x1 - x0, kNoReuseSurface);
      if (!rec->tally.empty())
        std::fill_n(rec->tally.begin() + static_cast<ptrdiff_t>((y * width + x0) * reuse->history_stride),
                    (x1 - x0) * reuse->history_stride, SoftTally{});
    }
  if (!reuse->previous) return;
  const ReuseFrame& previous = *reuse->previous;
  const ReuseOptions& options = reuse->options;
  scratch.skip_x0 = x0;
  scratch.skip_y0 = y0;
  scratch.skip_width = x1 - x0;
  scratch.skip.assign(static_cast<size_t>(x1 - x0) * (y1 - y0), 0);
  uint64_t taken = 0;
  const uint32_t all_lights = previous.lights >= 32 ? 0xFFFFFFFFu : (1u << previous.lights) - 1u;
  // The lights whose answers may be taken at `at` (a block's centre): not moved, and their shadow segments clear
  // of what moves (widened by the block's reach).
  auto takeable = [&](const glm::vec3& at, float pixels) {
    if (!reuse->motion) return reuse->previous_lights;
    const float spacing = glm::dot(at - frame.eye, reuse->now.w) / reuse->now.focal;
    const float margin = options.neighbour_reach * options.max_magnification * spacing * pixels;
    return lights_clear_of_motion(frame, previous, at, reuse->previous_lights, margin);
  };
  const float near = static_cast<float>(frame.primary_near);
  // A pixel taken whole (`lights` = all) or with the other lights left to trace from its surface point.
  auto take = [&](uint32_t x, uint32_t y, const GatheredPixel& pixel, uint32_t lights, uint32_t region,
                  size_t source) {
    // Beyond the near plane now (nearer, this trace's primary ray would pass it).
    if (!(glm::dot(pixel.position - frame.eye, reuse->now.w) > near)) return;
    // With slots, in the found pixel's cell (whose lights its fields are).
    if (frame.slots && region_of(frame, pixel.position) != region) return;
    scratch.skip[(y - y0) * scratch.skip_width + (x - x0)] = 1;
    ++taken;
    if (lights != all_lights) {
      SurfaceHit hit;
      hit.mesh = pixel.mesh;
      hit.position = pixel.position;
      hit.geometric_normal = pixel.normal;
      hit.shading_normal = pixel.shading;
      scratch.partial_hits.push_back(hit);
      scratch.partial_pixels.push_back({0, x, y});
      scratch.partial_known.push_back(pixel.known & lights);
      scratch.partial_reached.push_back(pixel.reached & lights);
      return;
    }
    out.set(x, y, pixel.mask);
    if (!rec) return;
    const size_t i = y * width + x;
    rec->position[i] = pixel.position;
    rec->normal[i] = pixel.normal;
    rec->shading[i] = pixel.shading;
    rec->mesh[i] = pixel.mesh;
    rec->mask[i] = pixel.mask;
    rec->known[i] = pixel.known;
    rec->reached[i] = pixel.reached;
    if (!rec->region.empty()) rec->region[i] = region;
    // The taken levels' accumulated samples come along (the source's tallies, where it kept them).
    if (!rec->tally.empty() && previous.tally.size() == previous.mesh.size() * reuse->history_stride)
      std::copy_n(previous.tally.begin() + static_cast<ptrdiff_t>(source * reuse->history_stride),
                  reuse->history_stride, rec->tally.begin() + static_cast<ptrdiff_t>(i * reuse->history_stride));
  };
  auto refreshed = [&](uint32_t x, uint32_t y) { return options.refresh && reuse_refresh_pixel(x, y, reuse->generation); };

  // Whole 4x4 blocks (the primary packets' blocks): one search, then each pixel's point on the found pixel's tangent
  // plane (which must face the eye at every pixel of the block).
  const uint32_t blocks_x = (x1 - x0 + 3) / 4, blocks_y = (y1 - y0 + 3) / 4;
  glm::vec2 guess(0.0f);
  for (uint32_t b = 0; b < blocks_x * blocks_y; ++b) {
    const uint32_t bx = x0 + (b % blocks_x) * 4, by = y0 + (b / blocks_x) * 4;
    const uint32_t ex = std::min(bx + 4, x1), ey = std::min(by + 4, y1);
    if (b % blocks_x == 0) guess = glm::vec2(static_cast<float>(bx) + 2.0f, static_cast<float>(by) + 2.0f);
    size_t source = 0;
    if (!reuse_gather_block(previous, reuse->now, bx, by, reuse->eye_motion, options, guess, source)) {
      guess = glm::vec2(static_cast<float>(bx) + 6.0f, static_cast<float>(by) + 2.0f);
      continue;
    }
    guess.x += 4.0f;
    const uint32_t lights = takeable(previous.position[source], 4.0f);
    GatheredPixel pixel;
    pixel.mesh = previous.mesh[source];
    pixel.mask = previous.mask[source];
    pixel.known = previous.known[source];
    pixel.reached = previous.reached[source];
    pixel.normal = previous.normal[source];
    pixel.shading = previous.shading[source];
    const glm::vec3& n = pixel.normal;
    const float plane = glm::dot(n, previous.position[source] - frame.eye);
    glm::vec3 dirs[16];
    bool facing = plane < 0.0f;
    for (uint32_t y = by; y < ey && facing; ++y)
      for (uint32_t x = bx; x < ex && facing; ++x) {
        glm::vec3& dir = dirs[(y - by) * 4 + (x - bx)];
        dir = reuse->columns[x] + reuse->rows[y] + reuse->forward;
        facing = glm::dot(n, dir) < 0.0f;
      }
    if (!facing) continue;  // the plane seen edge-on or from behind somewhere in the block
    for (uint32_t y = by; y < ey; ++y)
      for (uint32_t x = bx; x < ex; ++x) {
        if (refreshed(x, y)) continue;
        const glm::vec3& dir = dirs[(y - by) * 4 + (x - bx)];
        pixel.position = frame.eye + dir * (plane / glm::dot(n, dir));
        take(x, y, pixel, lights, previous.region.empty() ? 0u : previous.region[source], source);
      }
  }

  stats.reused_pixels += taken;
}

void append_partial_hits(TileScratch& scratch) {
  // The block pixels' slots follow the primary hits' (trace_tile's shadow rays group by slot / 16).
  uint32_t slot = scratch.hit_pixels.empty() ? 0 : scratch.hit_pixels.back().slot + 1;
  for (size_t i = 0; i < scratch.partial_hits.size(); ++i) {
    scratch.hits.push_back(scratch.partial_hits[i]);
    HitPixel px = scratch.partial_pixels[i];
    px.slot = slot++;
    scratch.hit_pixels.push_back(px);
    scratch.reuse_known.push_back(scratch.partial_known[i]);
    scratch.reuse_reached.push_back(scratch.partial_reached[i]);
    scratch.soft_known.push_back(0u);
    scratch.soft_mask.push_back(0u);
  }
  // Their soft lights start from nothing (rule 1 took them because nothing of their other lights had moved).
  scratch.soft_history.resize(scratch.hits.size() * scratch.history_stride);
}

void reuse_tile_hits(const FrameSetup& frame, TileScratch& scratch, TraceStats& stats) {
  const size_t hits = scratch.hits.size();
  scratch.reuse_known.assign(hits, 0u);
  scratch.reuse_reached.assign(hits, 0u);
  scratch.soft_known.assign(hits, 0u);
  scratch.soft_mask.assign(hits, 0u);
  const ReuseSetup* reuse = frame.reuse;
  scratch.history_stride = reuse && reuse->history ? reuse->history_stride : 0;
  scratch.soft_history.assign(hits * scratch.history_stride, SoftHistory{});
  if (!reuse) return;
  for (size_t h = 0; h < hits; ++h) {
    const SurfaceHit& hit = scratch.hits[h];
    const HitPixel& px = scratch.hit_pixels[h];
    ReuseQuery query;
    query.position = hit.position;
    query.normal = hit.geometric_normal;
    query.mesh = hit.mesh;
    query.spacing = glm::dot(hit.position - frame.eye, reuse->now.w) / reuse->now.focal;
    if (frame.slots) query.region = scratch.cells[h];
    // Soft samples accumulate on every pixel of a surface the previous trace saw, refreshed ones too (new samples
    // are taken there either way).
    ReuseCorners corners;
    const bool on_history = reuse->history && !reuse->moving_mesh[hit.mesh] &&
                            reuse_corners(*reuse->history, query, reuse->options, corners);
    if (on_history)
      for (uint32_t lights = reuse->history_lights; lights != 0; lights &= lights - 1) {
        const uint32_t slot = reuse->history_slot[static_cast<uint32_t>(std::countr_zero(lights))];
        if (slot < reuse->history_stride)
          scratch.soft_history[h * reuse->history_stride + slot] = reuse_soft_history(*reuse->history, corners, slot);
      }
    if (reuse->options.refresh && reuse_refresh_pixel(px.x, px.y, reuse->generation)) {
      ++stats.refreshed_pixels;
      continue;
    }
    if (reuse->sources.empty() || reuse->moving_mesh[hit.mesh]) continue;
    uint32_t known = 0, reached = 0, soft_known = 0, soft_mask = 0;
    for (const ReuseSetup::Source& source : reuse->sources) {
      // The history's corners are rule 2's in that frame (found once).
      const uint32_t asked = source.lights & ~known;
      ReuseAnswer answer = source.frame != reuse->history ? reuse_lookup(*source.frame, query, asked, reuse->options)
                           : on_history                   ? reuse_answer(*source.frame, corners, asked)
                                                          : ReuseAnswer{};
      for (uint32_t li = 0; li < 32; ++li) {  // soft lights whose four neighbours hold one level
        const uint32_t bit = 1u << li, field = reuse->field_bits[li];
        if (!(reuse->soft_lights & bit & ~soft_known) || (answer.agree & field) != field) continue;
        soft_known |= bit;
        soft_mask |= answer.mask & field;
      }
      if (answer.known && reuse->motion) {
        // X's neighbours' segments lie within the reach of X's, so the boxes are widened by it.
        const float margin = reuse->options.neighbour_reach * reuse->options.max_magnification * query.spacing;
        answer.known = lights_clear_of_motion(frame, *source.frame, hit.position, answer.known, margin);
        answer.reached &= answer.known;
      }
      known |= answer.known;
      reached |= answer.reached;
      // Every light any source could answer is answered.
      if ((reuse->usable_lights & ~known) == 0 && (reuse->soft_lights & ~soft_known) == 0) break;
    }
    scratch.reuse_known[h] = known;
    scratch.reuse_reached[h] = reached;
    scratch.soft_known[h] = soft_known;
    scratch.soft_mask[h] = soft_mask;
  }
}

void record_reuse_tile(const FrameSetup& frame, const TileScratch& scratch, const VisibilityBuffer& out) {
  ReuseFrame* rec = frame.reuse ? frame.reuse->record : nullptr;
  if (!rec) return;
  const size_t width = rec->camera.extent.width;
  for (size_t h = 0; h < scratch.hits.size(); ++h) {
    const SurfaceHit& hit = scratch.hits[h];
    if (frame.reuse->moving_mesh[hit.mesh]) continue;  // never a source: left kNoReuseSurface
    const uint32_t x = scratch.hit_pixels[h].x, y = scratch.hit_pixels[h].y;
    const size_t i = y * width + x;
    rec->position[i] = hit.position;
    rec->normal[i] = hit.geometric_normal;
    rec->shading[i] = hit.shading_normal;
    rec->mesh[i] = hit.mesh;
    rec->mask[i] = out.get(x, y);
    rec->known[i] = scratch.reuse_known[h];
    rec->reached[i] = scratch.reuse_reached[h];
    if (!rec->region.empty()) rec->region[i] = scratch.cells[h];
  }
}

void finish_reuse_record(const FrameSetup& frame, uint32_t workers) {
  ReuseFrame* rec = frame.reuse ? frame.reuse->record : nullptr;
  if (!rec) return;
  constexpr uint32_t kRowsPerJob = 8;
  const uint32_t jobs = (rec->cells_y + kRowsPerJob - 1) / kRowsPerJob;
  run_tiles(
      tile_workers(workers, jobs), jobs,
      [&](uint32_t, uint32_t job) {
        finish_reuse_cells(*rec, job * kRowsPerJob, std::min(rec->cells_y, (job + 1) * kRowsPerJob),
                           frame.reuse->options);
      },
      "reuse record");
  finish_reuse_distances(*rec);
}

}  // namespace dhr::server::detail
