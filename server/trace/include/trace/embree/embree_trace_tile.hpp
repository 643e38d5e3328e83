// Internal to the Embree tracer: everything one tile needs, and the tile kernel (public for bench/trace_bench and
// the primary-ray test, which replay exactly the tracer's rays). Includes go one way: the tracer includes this.
#pragma once
#include "scene/light_slots.hpp"
#include "scene/lighting.hpp"
#include "trace/embree/embree_scene.hpp"
#include "trace/embree/shadow_query.hpp"
#include "trace/reuse/reuse_frame.hpp"
#include "trace/visibility_tracer.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace dhr::server::detail {

// One trace's reuse (trace/reuse): where answers may come from and where this trace's go (embree_reuse_tile.cpp).
struct ReuseSetup {
  struct Source {
    const ReuseFrame* frame = nullptr;
    uint32_t lights = 0;  // lights it may answer (rule 2): traced then, hard now, not moved since
  };
  std::vector<Source> sources;  // tried in order
  uint32_t usable_lights = 0;   // the union of their lights
  // Soft lights whose levels rule 2 may take (not moved in any source; none when anything moves), and each light's
  // field bits in the mask.
  uint32_t soft_lights = 0;
  std::array<uint32_t, kMaxLights> field_bits{};
  // Rule 1 (whole pixels) from the eye's previous trace (the same layout): its answers for previous_lights (those
  // that did not move since) are taken; a block that needs another light's (moved, or whose shadow segments meet
  // what moves) skips its primary rays and traces only those lights from the block's surface points.
  const ReuseFrame* previous = nullptr;
  uint32_t previous_lights = 0;
  // Soft samples accumulate onto the eye's previous trace's (ReuseOptions::soft_history; not with light slots, nor
  // while anything moves): its tallies of history_lights (soft lights that did not move) are added to; the record
  // keeps tallies when soft_history is on and the layout has soft fields: history_stride per pixel (the layout's
  // soft lights), light i's at history_slot[i].
  const ReuseFrame* history = nullptr;
  uint32_t history_lights = 0;
  uint32_t history_stride = 0;
  std::array<uint8_t, kMaxLights> history_slot{};
  ReuseProjection now;          // this trace's camera
  ReuseMotion eye_motion;       // reuse_motion(previous, now)
  // Unnormalized view rays in float, columns[x] + rows[y] + forward (FrameSetup's tables): where a taken pixel's
  // ray meets the plane it is taken on.
  std::vector<glm::vec3> columns, rows;
  glm::vec3 forward{0.0f};
  bool near_geometry = false;   // rule 1 refused: geometry near an eye could cross the near plane
  ReuseFrame* record = nullptr;
  ReuseOptions options;
  uint32_t generation = 0;            // this trace's: picks the refreshed pixels
  std::vector<uint8_t> moving_mesh;   // per mesh: 1 = on a moving node (never reused from or into)
  std::vector<ReuseBox> moving_boxes; // moving meshes now (relative frame)
  bool motion = false;                // some box, now or in a source: shadow segments are tested against them
};

// Per-frame constants shared read-only by all threads.
struct FrameSetup {
  const EmbreeScene* scene = nullptr;
  const Camera* camera = nullptr;
  glm::vec3 eye{0.0f};          // eye position in the scene's relative frame
  glm::dmat3 world_from_eye{1.0};
  // Primary-ray tables: the terms of R * (tx, ty, -1) (R = world_from_eye) that depend on the column or
  // the row only, so a pixel costs two additions, not the camera maths (primary_direction sums them in
  // the product's own order: bit-identical to normalize(R * camera.eye_ray(x + 0.5, y + 0.5))).
  std::vector<glm::dvec3> ray_columns;  // R[0] * tx of column x
  std::vector<glm::dvec3> ray_rows;     // R[1] * ty of row y
  glm::dvec3 ray_forward{0.0};          // R[2] * -1
  double primary_near = kClipNearPlane;  // TracerOptions::primary_near
  std::vector<PackedLight> lights;      // all lights, relative frame
  std::vector<uint32_t> active_lights;  // indices of lights not culled for this view (trace_tile traces these)
  // Where light i's bit goes in the mask: its field's first bit (make_frame_setup: field[i]; the tracer sets the
  // offset in a layout with level fields, whose soft lights trace_soft_tile traces, not trace_tile).
  std::array<uint8_t, kMaxSlotLights> bit{};
  // Light slots (scene/light_slots.hpp): nullptr for at most kMaxLights lights, light i being field i. Else light
  // i is field field[i], and a hit traces only the lights its cell holds (select_cell_lights).
  const LightSlots* slots = nullptr;
  std::array<uint8_t, kMaxSlotLights> field{};
  uint32_t fields = 0;                     // fields traced (requested)
  // With slots, the hard fields' bits, which a hit's mask starts with: a hard field is 0 only where its cell's light
  // contributes (in range, facing it, not culled) and its ray is occluded. A field whose light cannot add anything
  // is never looked at by the client's shading, and 1 there keeps a light's lit area from ending in an edge the
  // codec must code at every range circle and terminator (about half the bytes of 64 lights: docs/server.md).
  uint32_t idle_lit = 0;
  std::vector<uint8_t> light_state;        // with slots, per light: kLightInactive, kLightHard or kLightSoft
  uint32_t culled_lights = 0;
  SkipOptions skip;
  bool primary_packets = true;
  ShadowQuery shadow_query = ShadowQuery::kStream;
  const ReuseSetup* reuse = nullptr;  // nullptr: every pair traced, nothing recorded
};

inline constexpr uint8_t kLightInactive = 0, kLightHard = 1, kLightSoft = 2;

// One queued occlusion ray's destination.
struct PendingShadowRay {
  uint32_t slot = 0;         // pixel slot within the tile (block * 16 + lane): packets group by block
  uint32_t hit = 0;          // index into TileScratch::hits
  uint32_t light = 0;        // light index (bit)
  bool contributes = false;  // light_test said kContributes (else traced only because a skip is off)
};

// Where a hit pixel is.
struct HitPixel {
  uint32_t slot = 0;
  uint32_t x = 0;
  uint32_t y = 0;
};

// Per-thread buffers reused from tile to tile. Only pixels whose primary ray hit are stored (in slot
// order), so background pixels cost no bookkeeping past their primary ray.
struct TileScratch {
  std::vector<SurfaceHit> hits;
  std::vector<HitPixel> hit_pixels;  // parallel to hits
  std::vector<RTCRay> rays;
  std::vector<PendingShadowRay> pending;
  std::vector<uint32_t> masks;  // parallel to hits
  // Reuse, parallel to hits: lights answered without a ray and their answers; after the trace, every light whose
  // occlusion is known at the hit (reused or traced) and those reached (what the record keeps).
  std::vector<uint32_t> reuse_known;
  std::vector<uint32_t> reuse_reached;
  // Rule 2 for soft lights, parallel to hits: the soft lights whose levels were taken, and the mask holding them.
  std::vector<uint32_t> soft_known;
  std::vector<uint32_t> soft_mask;
  // Per hit and light (h * ReuseSetup::history_stride + light): what the eye's previous trace accumulated there of
  // each soft light (SoftHistory::samples 0: nothing); empty without history.
  std::vector<SoftHistory> soft_history;
  uint32_t history_stride = 0;
  // Rule 1: the tile's pixels answered whole (no primary ray), by pixel within the tile.
  std::vector<uint8_t> skip;  // (y - skip_y0) * skip_width + (x - skip_x0): 1 = gathered
  // Rule 1 blocks with lights to trace: their pixels' surface points (no primary ray), appended to `hits` after the
  // primary rays with their taken answers (append_partial_hits).
  std::vector<SurfaceHit> partial_hits;
  std::vector<HitPixel> partial_pixels;
  std::vector<uint32_t> partial_known, partial_reached;
  uint32_t skip_x0 = 0, skip_y0 = 0, skip_width = 0;
  // Light slots, parallel to hits: the hit's grid cell (LightSlots::cell_of, found once: reuse, the record and
  // select_cell_lights read it), the lights of that cell, one per field (LightSlots::lights_in); and the tile's
  // active lights that some hit's cell holds, ascending.
  std::vector<uint32_t> cells;
  std::vector<const uint16_t*> cell_lights;
  std::vector<uint32_t> tile_lights;
  bool skipped(uint32_t x, uint32_t y) const {
    return !skip.empty() && skip[(y - skip_y0) * skip_width + (x - skip_x0)] != 0;
  }
};

// The frame constants for one camera: the eye in the scene's relative frame, the packed lights and which of
// the first `requested` of them `skip.cull_lights` leaves active (lights past `requested` are never
// tested or traced). Query kinds stay at their defaults (the tracer sets them).
// With `slots` (not the identity), `requested` counts fields: every light of the first `requested` slots is tested.
FrameSetup make_frame_setup(const EmbreeScene& scene, const std::vector<SceneLight>& lights, const Camera& camera,
                            const SkipOptions& skip, uint32_t requested = UINT32_MAX,
                            const LightSlots* slots = nullptr);

// Light slots: scratch.cells for hits [from, end) (the surface points' grid cells).
void find_hit_cells(const FrameSetup& frame, TileScratch& scratch, size_t from);

// Light slots: scratch.cell_lights and tile_lights for the tile's hits (their scratch.cells); a requested field whose cell holds no light
// counts as skipped_out_of_range, one whose light is culled as skipped_culled_light.
void select_cell_lights(const FrameSetup& frame, TileScratch& scratch, TraceStats& stats);

// Unit primary-ray direction through pixel (x, y)'s centre, relative frame (from the frame's tables).
inline glm::vec3 primary_direction(const FrameSetup& frame, uint32_t x, uint32_t y) {
  return glm::vec3(glm::normalize((frame.ray_columns[x] + frame.ray_rows[y]) + frame.ray_forward));
}

// Where a primary ray along `dir` starts: the client's near plane (frame.primary_near along the view axis),
// so nothing the client's rasterizer clips is traced in its place.
inline float primary_tnear(const FrameSetup& frame, const glm::vec3& dir) {
  return static_cast<float>(frame.primary_near / glm::dot(glm::dvec3(dir), frame.ray_forward));
}

// Point/spot shadow rays stop this fraction short of the light, so geometry exactly at the light (a bulb's
// surface through the light's centre) does not count as an occluder of its own light.
inline constexpr float kShadowTfarScale = 1.0f - 1e-5f;

// The occlusion ray for one surface point and light (sample: its light test): from the surface point offset
// along the geometric normal on the light's side (ray_offset.hpp) toward the light; tfar = the distance to a
// point/spot light times kShadowTfarScale, infinite for a directional one. The soft-visibility sampler
// (trace/soft) builds its punctual rays with it, so they are the hard tracer's rays.
void make_shadow_ray(const PackedLight& light, const SurfaceHit& hit, const LightSample& sample,
                     const RayOffset& offset, RTCRay& out);

// Primary rays of pixels [x0, x1) x [y0, y1): scratch.hits / hit_pixels get the hit pixels (in 4x4-block slot
// order); primary_rays and background_pixels are added to `stats`. trace_tile's first step; the soft-visibility
// image reuses it so that its surface points are the hard tracer's.
void trace_primary_tile(const FrameSetup& frame, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1,
                        TileScratch& scratch, TraceStats& stats);

// One surface point and light's test: true when frame.skip skips the pair (counted in `stats` by reason).
bool pair_skipped(const FrameSetup& frame, const LightSample& sample, TraceStats& stats);

// One surface point and light: true with the occlusion ray to trace (and whether the light contributes, else
// the ray is traced only because a skip is off), or false when frame.skip skips the pair (counted in `stats`
// by reason). bench/trace_bench uses it to replay exactly the tracer's rays.
bool shadow_ray_for(const FrameSetup& frame, const PackedLight& light, const SurfaceHit& hit, TraceStats& stats,
                    RTCRay& out_ray, bool& out_contributes);

// Reuse for one trace: the sources' usable lights (`hard_lights` of those traced now, not moved since), whether
// whole pixels may come from the previous trace, the moving meshes and their boxes now, and the record (reset for
// `camera`, its light state written). Sources that are not valid or were traced with another layout are left out.
ReuseSetup make_reuse_setup(const EmbreeScene& scene, const FrameSetup& frame, const ReuseRequest& request,
                            const VisibilityLayout& layout, double scene_time);

// Rule 1 for the tile's pixels: those answered whole (counted in stats.reused_pixels) get their masks in `out`
// and their surfaces in the record, and are marked in scratch.skip; refreshed pixels are left to trace. Every
// other pixel of the record's tile starts without a surface (kNoReuseSurface).
void gather_tile(const FrameSetup& frame, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, TileScratch& scratch,
                 VisibilityBuffer& out, TraceStats& stats);

// Appends rule 1's partial blocks (scratch.partial_*) to the hits, with their answers in reuse_known / reuse_reached.
void append_partial_hits(TileScratch& scratch);

// Rule 2: fills scratch.reuse_known / reuse_reached for the tile's hits (those of its primary rays) from
// frame.reuse's sources (all zero without reuse, on refreshed pixels (counted in stats.refreshed_pixels) and on
// moving meshes).
void reuse_tile_hits(const FrameSetup& frame, TileScratch& scratch, TraceStats& stats);

// Writes the tile's hit pixels into frame.reuse->record (not those on moving meshes): surface, mask (from `out`,
// soft fields included) and known and reached lights (scratch.reuse_known / reuse_reached after the trace).
void record_reuse_tile(const FrameSetup& frame, const TileScratch& scratch, const VisibilityBuffer& out);

// After every tile: the record's discontinuity distances (trace/reuse), on `workers` threads.
void finish_reuse_record(const FrameSetup& frame, uint32_t workers);

// Traces pixels [x0, x1) x [y0, y1) into `out` and adds to `stats` (counts only, no times).
void trace_tile(const FrameSetup& frame, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, VisibilityBuffer& out,
                TraceStats& stats, TileScratch& scratch);

}  // namespace dhr::server::detail
