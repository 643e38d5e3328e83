// The server's visibility tracer: for one eye's guard-banded camera, one bit per light per pixel,
// 1 = the light reaches the pixel's surface point (unoccluded, facing it, in range and cone).
// Two backends behind this interface: Vulkan ray tracing (GPUs; lavapipe for tests) and Embree (CPUs,
// also the reference). Both produce identical bits except at silhouettes / shadow boundaries.
#pragma once
#include "math/projection.hpp"
#include "trace/reuse/reuse_frame.hpp"
#include "trace/soft/soft_options.hpp"
#include "scene/light_slots.hpp"
#include "scene/scene.hpp"
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dhr::server {

enum class TracerBackend { kAuto, kEmbree, kVulkan };
// "auto" | "embree" | "vulkan"; throws std::invalid_argument otherwise.
TracerBackend parse_tracer_backend(const std::string& text);
const char* tracer_backend_name(TracerBackend backend);

// Every skip is switchable so tests can compare against the exhaustive path (identical bits).
struct SkipOptions {
  bool backfacing = true;    // no shadow ray when N.L <= 0 (bit is 0 either way)
  bool out_of_range = true;  // no shadow ray beyond the light's range or outside a spot cone
  bool cull_lights = true;   // lights whose range cannot reach the view frustum: no rays at all
  static SkipOptions none() { return SkipOptions{false, false, false}; }
};

// CPU tracer threads at most (TracerOptions::threads, --threads): far above any core count a server has, low
// enough that a typo cannot ask the system for millions of threads.
inline constexpr uint32_t kMaxTracerThreads = 256;

struct TracerOptions {
  SkipOptions skip;
  uint32_t threads = 0;  // CPU backends: 0 = all cores; at most kMaxTracerThreads
  // Primary rays start at this depth along the view axis: the client's near plane, so nothing it clips is
  // traced in place of what it shows (a scene drawn at another scale would scale it too).
  double primary_near = kClipNearPlane;
  // Lights with an extent in trace_layout's soft fields (Embree backend; the Vulkan backend traces their centres).
  SoftOptions soft;
  // Vulkan backend: device preference "auto" | "gpu" | "lavapipe"; validation layer on/off.
  std::string vk_device = "auto";
  bool vk_validation = false;
};

// What building the acceleration structures cost.
struct AccelStats {
  double build_ms = 0.0;
  uint64_t bytes = 0;        // acceleration-structure memory (after compaction where applicable)
  uint64_t triangles = 0;
  uint32_t blas_count = 0;   // Vulkan: one per geometry; Embree: geometries in the scene
  uint32_t instance_count = 0;
};

struct TraceStats {
  uint64_t pixels = 0;
  uint64_t background_pixels = 0;      // primary ray missed: no shadow rays
  uint64_t primary_rays = 0;
  uint64_t shadow_rays = 0;            // traced
  uint64_t skipped_backfacing = 0;     // pixel-light pairs with N.L <= 0
  uint64_t skipped_out_of_range = 0;   // beyond range / outside spot cone
  uint64_t skipped_culled_light = 0;   // pixel-light pairs of lights culled for this view
  uint32_t lights_culled = 0;          // of the traced lights
  uint32_t lights_unrequested = 0;     // lights past trace_lights' count: no light test, no ray at all
  // Soft lights (a layout with level fields, trace_layout): their pairs, sampled over the light's extent.
  uint64_t soft_pairs = 0;               // hit pixel x soft light not culled
  uint64_t soft_contributing_pairs = 0;  // of those, the light test passed: samples were taken
  uint64_t soft_refined_pairs = 0;       // of those, the first samples disagreed: sampled up to the maximum
  uint64_t soft_shadow_rays = 0;         // their occlusion rays (also counted in shadow_rays)
  // Reuse (trace_reusing, trace/reuse): pixels answered whole from the eye's previous trace (no primary ray),
  // contributing pixel-light pairs of traced pixels answered from a source instead of a ray, and the hit pixels
  // traced in full as this frame's refresh share.
  uint64_t reused_pixels = 0;
  uint64_t reused_pairs = 0;
  uint64_t refreshed_pixels = 0;
  // Rays per hit pixel per soft light (soft_shadow_rays / soft_pairs; 0 without soft pairs).
  double soft_rays_per_pair() const;
  // Share of contributing soft pairs that needed more than the first samples.
  double soft_refined_share() const;
  double trace_ms = 0.0;               // wall time of the whole trace call (host)
  double gpu_ms = -1.0;                // GPU timestamp time (Vulkan), -1 when not measured

  // Adds `other`'s per-pixel and per-ray counters (pixels through soft_shadow_rays, not the light counts or the
  // times): a tracer's tiles into its trace, or traces into a run's totals.
  void add_counts(const TraceStats& other);
};

class VisibilityTracer {
 public:
  virtual ~VisibilityTracer() = default;
  virtual TracerBackend backend() const = 0;
  // Device and driver, e.g. "Embree 3.13.5, 2 threads" or "llvmpipe (LLVM 15.0.6, 256 bits), Mesa 25.0.7".
  virtual std::string device_description() const = 0;
  virtual const AccelStats& accel_stats() const = 0;
  // The fields of every mask: the scene's lights, or with more than kMaxLights lights the slots they share.
  virtual uint32_t light_count() const = 0;
  // With more than kMaxLights lights, the slots they share (scene/light_slots.hpp): field f of a pixel's mask is
  // the light slot f holds in the cell of the pixel's surface point. nullptr: field i is light i (and a backend
  // without slots refuses such a scene).
  virtual const LightSlots* light_slots() const { return nullptr; }

  // Traces one eye. `out` is (re)sized to camera.extent with the scene's light count.
  // Throws std::invalid_argument for an unusable camera (see validate_camera). The Embree backend allows
  // concurrent calls (e.g. both eyes at once); the tracer's state is read-only while tracing.
  virtual void trace(const Camera& camera, VisibilityBuffer& out, TraceStats& out_stats) = 0;

  // Traces one eye for the scene's first `lights` lights only (clamped to light_count()): a client asked for
  // fewer than the scene has. The others cost nothing (TraceStats::lights_unrequested counts them); `out`
  // gets `lights` lights in the narrowest mask width, with the bits trace() gives those lights. Both backends
  // override this; the default, for wrappers that implement only trace(), traces all and drops the rest.
  virtual void trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out, TraceStats& out_stats);

  // Moves the traced scene to scene time `t` (seconds; scene/scene_animation.hpp): geometry on moving nodes and
  // lights (light_at) as they are at t. Not concurrent with tracing. The default does nothing: a backend without
  // motion traces the scene at rest (the Vulkan backend warns once when asked for t != 0 in an animated scene).
  // With `overrides`, app-moved nodes are where scene/node_overrides.hpp puts them at t (the caller keeps them alive
  // for the call).
  virtual void set_scene_time(double t, const NodeOverrides* overrides = nullptr) {
    (void)t;
    (void)overrides;
  }
  // The nodes set_scene_time may move (SceneAnimation::nodes: animated, movable, or below one), for checking the
  // node of an app's transform; nullptr for a tracer that moves nothing (an app's transforms are then for unknown
  // nodes).
  virtual const SceneAnimation* scene_animation() const { return nullptr; }
  // Whether set_scene_time changes what is traced (the scene has animation and this backend plays it). A caller
  // that traces a moving tracer from several threads serializes set_scene_time and the traces at that time.
  virtual bool moves() const { return false; }
  // Wall time of the last set_scene_time's acceleration-structure update (vertices, refits, top level), ms; 0
  // for a tracer that does not move.
  virtual double last_motion_update_ms() const { return 0.0; }

  // Per scene light: it has an extent (SceneLight::has_extent(), a soft light). Empty for tracers that only
  // know hard bits (their layout is always the hard one).
  virtual std::vector<bool> light_extents() const { return {}; }

  // Traces one eye in `layout` (its light_count lights: the scene's first ones, at most light_count()):
  // `out` gets layout.total_bits() bits per mask (VisibilityBuffer::light_count), each light in its field.
  // A hard layout is exactly trace_lights. Soft fields: both backends write the Gray-coded level of the light's
  // sampled visibility (trace/soft, as trace_soft_image: same seeds, same samples; the Vulkan backend's shader
  // takes the same sample points, within the bound of docs/server.md); this default, for tracers that know only
  // hard bits, traces the light's centre as a punctual light and writes level 0 or the top level (the hard bit,
  // widened). Hard fields are trace_lights' bits in all.
  virtual void trace_layout(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out,
                            TraceStats& out_stats);

  // Traces like trace_layout, but a contributing pixel-light pair of a hard field takes its occlusion from
  // request's earlier traces where the reuse rule allows (trace/reuse/reuse_frame.hpp), and this trace's surfaces
  // and answers go to request.record (when not nullptr) for later traces. The Embree backend reuses; this default
  // (the Vulkan backend) traces every pair and leaves request.record invalid.
  virtual void trace_reusing(const Camera& camera, const VisibilityLayout& layout, const ReuseRequest& request,
                             VisibilityBuffer& out, TraceStats& out_stats);
};

// The soft-capable layout of the first `lights` lights of `extents` (light_extents()): for_lights of their
// extents, or hard(lights) when `extents` is empty.
VisibilityLayout layout_for_lights(const std::vector<bool>& extents, uint32_t lights);

// Writes the one-bit-per-light masks of `hard` into `layout`'s fields: a hard light's bit as it is, a soft
// light's bit as level 0 or the top level (Gray-coded). `out` gets layout.total_bits() bits per mask.
void widen_to_layout(const VisibilityBuffer& hard, const VisibilityLayout& layout, VisibilityBuffer& out);

// The checks every backend makes before tracing `layout` for `camera` with a scene of `scene_lights` lights:
// throws std::invalid_argument for an unusable camera (validate_camera), an image wider or taller than
// kMaxBufferDimension, or a layout of more lights than the scene has.
void check_trace_request(const Camera& camera, const VisibilityLayout& layout, uint32_t scene_lights);

// Keeps lights [0, lights) of `buffer` (no-op when it has no more), narrowing its mask width to match.
void keep_first_lights(VisibilityBuffer& buffer, uint32_t lights);

// The name of a real (non-CPU) GPU whose Vulkan driver offers ray tracing, or std::nullopt (no driver,
// only lavapipe, no ray tracing). Creates and drops a Vulkan context: call once, not per frame.
std::optional<std::string> find_ray_tracing_gpu();

// Builds the acceleration structures for `scene` and returns a ready tracer. kAuto picks Vulkan on a
// GPU with ray tracing, Embree otherwise. Throws std::runtime_error with a one-line reason on failure.
std::unique_ptr<VisibilityTracer> create_tracer(TracerBackend backend, const Scene& scene,
                                                const TracerOptions& options = {});

}  // namespace dhr::server
