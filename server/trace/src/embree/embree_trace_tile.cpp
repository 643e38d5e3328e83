#include "trace/embree/embree_trace_tile.hpp"

#include "trace/ray_offset.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cstring>
#include <limits>

namespace dhr::server::detail {
namespace {

constexpr uint32_t kBlock = 4;  // primary packets cover 4x4 pixels
constexpr uint32_t kBlockPixels = kBlock * kBlock;
// A block with at most this many pixels to trace (reuse took the others, or the image's edge cuts it) traces them
// one ray at a time: a packet costs about as much however few of its lanes are on, and with reuse most blocks
// have only their one refreshed pixel left (docs/performance.md, "Sparse blocks"). Same bits either way
// (EmbreeProperties.SingleRaysAndPacketsGiveTheSameBits).
constexpr uint32_t kMaxSingleRays = kBlockPixels / 2;
// Appends a primary hit of pixel (x, y) (tile slot `slot`) to the scratch lists.
void add_hit(TileScratch& scratch, const SurfaceHit& hit, uint32_t slot, uint32_t x, uint32_t y) {
  scratch.hits.push_back(hit);
  scratch.hit_pixels.push_back({slot, x, y});
}

// Primary rays of the 4x4 block at (bx, by) whose first slot is `slot0`; lanes outside the image are not
// traced or counted. Hits go to the scratch lists in lane order; misses are only counted.
void trace_primary_block(const FrameSetup& frame, uint32_t bx, uint32_t by, uint32_t x1, uint32_t y1,
                         uint32_t slot0, TileScratch& scratch, TraceStats& stats) {
  const EmbreeScene& scene = *frame.scene;
  const uint32_t lanes_x = std::min(kBlock, x1 - bx), lanes_y = std::min(kBlock, y1 - by);
  // Lanes inside the image and not answered whole by reuse (TileScratch::skipped).
  uint32_t inside = 0;
  alignas(64) int valid[kBlockPixels];
  for (uint32_t lane = 0; lane < kBlockPixels; ++lane) {
    const uint32_t lx = lane % kBlock, ly = lane / kBlock;
    const bool in = lx < lanes_x && ly < lanes_y && !scratch.skipped(bx + lx, by + ly);
    valid[lane] = in ? -1 : 0;
    inside += in ? 1 : 0;
  }
  if (inside == 0) return;
  stats.primary_rays += inside;
  const size_t hits_before = scratch.hits.size();
  if (!frame.primary_packets || inside <= kMaxSingleRays) {
    for (uint32_t lane = 0; lane < kBlockPixels; ++lane) {
      const uint32_t x = bx + lane % kBlock, y = by + lane / kBlock;
      if (!valid[lane]) continue;
      const glm::vec3 dir = primary_direction(frame, x, y);
      if (const auto hit = scene.intersect(frame.eye, dir, primary_tnear(frame, dir)))
        add_hit(scratch, *hit, slot0 + lane, x, y);
    }
    stats.background_pixels += inside - (scratch.hits.size() - hits_before);
    return;
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRayHit16 rh;
  for (uint32_t lane = 0; lane < kBlockPixels; ++lane) {
    const uint32_t lx = lane % kBlock, ly = lane / kBlock;
    const bool in = valid[lane] != 0;
    const glm::vec3 dir = in ? primary_direction(frame, bx + lx, by + ly) : glm::vec3(0.0f, 0.0f, -1.0f);
    rh.ray.org_x[lane] = frame.eye.x;
    rh.ray.org_y[lane] = frame.eye.y;
    rh.ray.org_z[lane] = frame.eye.z;
    rh.ray.dir_x[lane] = dir.x;
    rh.ray.dir_y[lane] = dir.y;
    rh.ray.dir_z[lane] = dir.z;
    rh.ray.tnear[lane] = in ? primary_tnear(frame, dir) : 0.0f;
    rh.ray.tfar[lane] = std::numeric_limits<float>::infinity();
    rh.ray.time[lane] = 0.0f;
    rh.ray.mask[lane] = 0xFFFFFFFFu;
    rh.ray.id[lane] = lane;
    rh.ray.flags[lane] = 0;
    rh.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
  }
  rtcIntersect16(valid, scene.handle(), &context, &rh);
  for (uint32_t lane = 0; lane < kBlockPixels; ++lane) {
    if (!valid[lane] || rh.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) continue;
    const glm::vec3 dir(rh.ray.dir_x[lane], rh.ray.dir_y[lane], rh.ray.dir_z[lane]);
    add_hit(scratch, scene.surface(rh.hit.geomID[lane], rh.hit.primID[lane], rh.hit.u[lane], rh.hit.v[lane], dir),
            slot0 + lane, bx + lane % kBlock, by + lane / kBlock);
  }
  stats.background_pixels += inside - (scratch.hits.size() - hits_before);
}

// Runs the queued occlusion rays in the configured way; afterwards tfar < 0 marks an occluded ray.
void trace_shadow_rays(const FrameSetup& frame, TileScratch& scratch) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::vector<RTCRay>& rays = scratch.rays;
  if (rays.empty()) return;
  switch (frame.shadow_query) {
    case ShadowQuery::kSingle:
      context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
      for (RTCRay& ray : rays) rtcOccluded1(frame.scene->handle(), &context, &ray);
      return;
    case ShadowQuery::kStream:
      // Runs of rays from neighbouring pixels toward one light: coherent, Embree packs them itself.
      context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      rtcOccluded1M(frame.scene->handle(), &context, rays.data(), static_cast<unsigned>(rays.size()), sizeof(RTCRay));
      return;
    case ShadowQuery::kPackets: {
      context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      alignas(64) RTCRay16 packet;
      alignas(64) int valid[kBlockPixels];
      for (size_t begin = 0; begin < rays.size();) {
        // A run: same light, same 4x4 block (at most 16 rays).
        const uint32_t light = scratch.pending[begin].light, block = scratch.pending[begin].slot / kBlockPixels;
        size_t end = begin;
        while (end < rays.size() && end - begin < kBlockPixels && scratch.pending[end].light == light &&
               scratch.pending[end].slot / kBlockPixels == block)
          ++end;
        for (uint32_t i = 0; i < kBlockPixels; ++i) {
          const bool on = begin + i < end;
          const RTCRay& r = rays[on ? begin + i : begin];
          valid[i] = on ? -1 : 0;
          packet.org_x[i] = r.org_x;
          packet.org_y[i] = r.org_y;
          packet.org_z[i] = r.org_z;
          packet.dir_x[i] = r.dir_x;
          packet.dir_y[i] = r.dir_y;
          packet.dir_z[i] = r.dir_z;
          packet.tnear[i] = r.tnear;
          packet.tfar[i] = r.tfar;
          packet.time[i] = 0.0f;
          packet.mask[i] = r.mask;
          packet.id[i] = i;
          packet.flags[i] = 0;
        }
        rtcOccluded16(valid, frame.scene->handle(), &context, &packet);
        for (size_t i = begin; i < end; ++i) rays[i].tfar = packet.tfar[i - begin];
        begin = end;
      }
      return;
    }
  }
}

}  // namespace

void make_shadow_ray(const PackedLight& light, const SurfaceHit& hit, const LightSample& sample,
                     const RayOffset& offset, RTCRay& out) {
  // Leave from the side of the surface the light is on (the geometric normal, not the shading normal).
  const glm::vec3 n = glm::dot(hit.geometric_normal, sample.l) >= 0.0f ? hit.geometric_normal : -hit.geometric_normal;
  const glm::vec3 origin = offset_ray_origin(hit.position, n, offset);
  if (light_eval::light_is_directional(light)) {
    out = make_rtc_ray(origin, sample.l, std::numeric_limits<float>::infinity());
    return;
  }
  const glm::vec3 d = glm::vec3(light.position_type) - origin;
  const float dist = glm::length(d);
  if (!(dist > 0.0f)) {
    out = make_rtc_ray(origin, sample.l, 0.0f);  // at the light: nothing can be in between
    return;
  }
  out = make_rtc_ray(origin, d / dist, dist * kShadowTfarScale);
}

FrameSetup make_frame_setup(const EmbreeScene& scene, const std::vector<SceneLight>& lights, const Camera& camera,
                            const SkipOptions& skip, uint32_t requested, const LightSlots* slots) {
  FrameSetup frame;
  frame.scene = &scene;
  frame.camera = &camera;
  frame.eye = scene.to_relative(camera.T_world_eye.position);
  frame.world_from_eye = glm::mat3_cast(glm::normalize(camera.T_world_eye.orientation));
  // The products of R * (tx, ty, -1) at the pixel centres, each computed once (see FrameSetup).
  const glm::dmat3& R = frame.world_from_eye;
  frame.ray_columns.resize(camera.extent.width);
  for (uint32_t x = 0; x < camera.extent.width; ++x) frame.ray_columns[x] = R[0] * camera.eye_ray(x + 0.5, 0.5).x;
  frame.ray_rows.resize(camera.extent.height);
  for (uint32_t y = 0; y < camera.extent.height; ++y) frame.ray_rows[y] = R[1] * camera.eye_ray(0.5, y + 0.5).y;
  frame.ray_forward = R[2] * -1.0;
  frame.lights = pack_lights(lights, scene.origin());
  frame.skip = skip;
  if (slots && slots->is_identity()) slots = nullptr;
  frame.slots = slots;
  for (uint32_t i = 0; i < lights.size() && i < kMaxSlotLights; ++i)
    frame.field[i] = frame.bit[i] = static_cast<uint8_t>(slots ? slots->slot_of(i) : i);
  if (!slots) {
    const uint32_t traced = static_cast<uint32_t>(std::min<size_t>(requested, lights.size()));
    frame.fields = traced;
    for (uint32_t i = 0; i < traced; ++i) {
      if (skip.cull_lights && !light_may_reach_view(lights[i], camera))
        ++frame.culled_lights;
      else
        frame.active_lights.push_back(i);
    }
    return frame;
  }
  // Slots: a light takes part when its field is requested (a dropped light never does); culled lights are counted
  // per hit whose cell holds them (select_cell_lights), as a field.
  frame.fields = std::min(requested, slots->slot_count());
  frame.idle_lit = frame.fields >= 32 ? 0xFFFFFFFFu : (1u << frame.fields) - 1u;  // the hard layout's fields
  frame.light_state.assign(lights.size(), kLightInactive);
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (slots->slot_of(i) == kNoSlotLight || slots->slot_of(i) >= frame.fields) continue;
    if (skip.cull_lights && !light_may_reach_view(lights[i], camera)) continue;
    frame.light_state[i] = kLightHard;
    frame.active_lights.push_back(i);
  }
  return frame;
}

void find_hit_cells(const FrameSetup& frame, TileScratch& scratch, size_t from) {
  const glm::dvec3 origin = frame.scene->origin();
  scratch.cells.resize(scratch.hits.size());
  for (size_t h = from; h < scratch.hits.size(); ++h)
    scratch.cells[h] = frame.slots->cell_of(glm::dvec3(scratch.hits[h].position) + origin);
}

void select_cell_lights(const FrameSetup& frame, TileScratch& scratch, TraceStats& stats) {
  const size_t hits = scratch.hits.size();
  scratch.cell_lights.resize(hits);
  scratch.tile_lights.clear();
  std::array<uint64_t, kMaxSlotLights / 64> seen{};
  // Neighbouring hits mostly share a cell: a row is looked through once per run of hits in it.
  const uint16_t* last = nullptr;
  uint64_t out_of_range = 0, culled = 0;  // per hit in `last`'s cell
  for (size_t h = 0; h < hits; ++h) {
    const uint16_t* row = frame.slots->lights_in(scratch.cells[h]);
    scratch.cell_lights[h] = row;
    if (row != last) {
      last = row;
      out_of_range = culled = 0;
      for (uint32_t f = 0; f < frame.fields; ++f) {
        const uint16_t li = row[f];
        if (li == kNoSlotLight) {
          ++out_of_range;
        } else if (frame.light_state[li] == kLightInactive) {
          ++culled;
        } else {
          seen[li / 64] |= uint64_t{1} << (li % 64);
        }
      }
    }
    stats.skipped_out_of_range += out_of_range;
    stats.skipped_culled_light += culled;
  }
  for (uint32_t w = 0; w < seen.size(); ++w)
    for (uint64_t bits = seen[w]; bits != 0; bits &= bits - 1)
      scratch.tile_lights.push_back(w * 64 + static_cast<uint32_t>(__builtin_ctzll(bits)));
}

bool pair_skipped(const FrameSetup& frame, const LightSample& sample, TraceStats& stats) {
  if (sample.test == LightTest::kOutOfRange && frame.skip.out_of_range) {
    ++stats.skipped_out_of_range;
    return true;
  }
  if (sample.test == LightTest::kBackfacing && frame.skip.backfacing) {
    ++stats.skipped_backfacing;
    return true;
  }
  return false;
}

bool shadow_ray_for(const FrameSetup& frame, const PackedLight& light, const SurfaceHit& hit, TraceStats& stats,
                    RTCRay& out_ray, bool& out_contributes) {
  const LightSample sample = sample_light(light, hit.position, hit.shading_normal);
  if (pair_skipped(frame, sample, stats)) return false;
  make_shadow_ray(light, hit, sample, frame.scene->ray_offset(), out_ray);
  out_contributes = sample.test == LightTest::kContributes;
  return true;
}

void trace_primary_tile(const FrameSetup& frame, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1,
                        TileScratch& scratch, TraceStats& stats) {
  const uint32_t blocks_x = (x1 - x0 + kBlock - 1) / kBlock, blocks_y = (y1 - y0 + kBlock - 1) / kBlock;
  // Block by block (slot = block * 16 + lane); only hits are kept, in slot order.
  scratch.hits.clear();
  scratch.hit_pixels.clear();
  for (uint32_t b = 0; b < blocks_x * blocks_y; ++b)
    trace_primary_block(frame, x0 + (b % blocks_x) * kBlock, y0 + (b / blocks_x) * kBlock, x1, y1, b * kBlockPixels,
                        scratch, stats);
}

void trace_tile(const FrameSetup& frame, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, VisibilityBuffer& out,
                TraceStats& stats, TileScratch& scratch) {
  // 1. Primary rays, but for pixels reuse answers whole. The tile's rows are cleared in one go first (background
  // and unlit pixels: 0); reuse writes the masks it answers, the trace those of hit pixels with a bit.
  const size_t mask_bytes = out.bytes_per_mask();
  for (uint32_t y = y0; y < y1; ++y)
    std::memset(out.data.data() + (size_t{y} * out.width + x0) * mask_bytes, 0, (x1 - x0) * mask_bytes);
  gather_tile(frame, x0, y0, x1, y1, scratch, out, stats);
  trace_primary_tile(frame, x0, y0, x1, y1, scratch, stats);
  if (frame.slots) find_hit_cells(frame, scratch, 0);
  // With reuse, a contributing pair whose occlusion a source answers takes that answer instead of a ray (rule 2);
  // then rule 1's blocks with lights left to trace join the hits.
  reuse_tile_hits(frame, scratch, stats);
  const size_t primary_hits = scratch.hits.size();
  append_partial_hits(scratch);
  if (frame.slots) find_hit_cells(frame, scratch, primary_hits);
  const uint32_t hits = static_cast<uint32_t>(scratch.hits.size());
  stats.skipped_culled_light += uint64_t{hits} * frame.culled_lights;
  if (frame.slots) select_cell_lights(frame, scratch, stats);

  // 2. Per pixel-light pair: skip (counted by reason) or queue an occlusion ray. Light-major, then block by
  // block: runs of up to 16 neighbouring rays toward the same light, which packets and streams bundle.
  scratch.rays.clear();
  scratch.pending.clear();
  scratch.masks.assign(hits, frame.slots ? frame.idle_lit : 0u);
  // With slots: the tile's lights, each for the hits whose cell holds it. Reuse's bits are fields (light i is field
  // i without slots).
  const std::vector<uint32_t>& lights = frame.slots ? scratch.tile_lights : frame.active_lights;
  for (uint32_t li : lights) {
    if (frame.slots && frame.light_state[li] != kLightHard) continue;
    const PackedLight& light = frame.lights[li];
    const uint32_t light_bit = 1u << frame.field[li];
    for (uint32_t h = 0; h < hits; ++h) {
      if (frame.slots && scratch.cell_lights[h][frame.field[li]] != li) continue;
      // shadow_ray_for's steps, the ray made only for a pair that reuse does not answer.
      const SurfaceHit& hit = scratch.hits[h];
      const LightSample sample = sample_light(light, hit.position, hit.shading_normal);
      if (pair_skipped(frame, sample, stats)) continue;
      const bool contributes = sample.test == LightTest::kContributes;
      if (contributes && (scratch.reuse_known[h] & light_bit)) {
        ++stats.reused_pairs;
        const bool reached = (scratch.reuse_reached[h] & light_bit) != 0;
        if (frame.slots && !reached) scratch.masks[h] &= ~(1u << frame.bit[li]);
        if (!frame.slots && reached) scratch.masks[h] |= 1u << frame.bit[li];
        continue;
      }
      RTCRay ray;
      make_shadow_ray(light, hit, sample, frame.scene->ray_offset(), ray);
      scratch.rays.push_back(ray);
      scratch.pending.push_back({scratch.hit_pixels[h].slot, h, li, contributes});
    }
  }
  stats.shadow_rays += scratch.rays.size();

  // 3. Occlusion queries (terminate on the first hit).
  trace_shadow_rays(frame, scratch);

  // 4. Bit = the light contributes and its ray reached it (or its reused answer says so); only hit pixels with a
  // bit are written.
  for (size_t r = 0; r < scratch.rays.size(); ++r) {
    const bool reached = scratch.rays[r].tfar >= 0.0f;  // Embree sets tfar = -inf when occluded
    const PendingShadowRay& p = scratch.pending[r];
    if (!p.contributes) continue;
    if (frame.slots) {  // the bit is set: cleared where the contributing light is occluded
      if (!reached) scratch.masks[p.hit] &= ~(1u << frame.bit[p.light]);
    } else if (reached) {
      scratch.masks[p.hit] |= 1u << frame.bit[p.light];
    }
    if (frame.reuse) {  // what the record keeps: this pair's occlusion is known now (by field)
      const uint32_t field_bit = 1u << frame.field[p.light];
      scratch.reuse_known[p.hit] |= field_bit;
      if (reached) scratch.reuse_reached[p.hit] |= field_bit;
    }
  }
  for (uint32_t h = 0; h < hits; ++h)
    if (scratch.masks[h] != 0u) out.set(scratch.hit_pixels[h].x, scratch.hit_pixels[h].y, scratch.masks[h]);
}

}  // namespace dhr::server::detail
