// Helpers of the stress suite (tests/stress, label `stress`): the long mode switch, the one-line report of
// each case's measured worst value (docs/stress.md is built from these lines), scene transforms, bit
// comparison and bookmark cameras.
#pragma once
#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "visibility/visibility.hpp"
#include "test_scenes.hpp"
#include "trace/visibility_tracer.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace dhr::stress {

// DHR_STRESS_LONG=1 (or any value but "0"): larger sizes, more cameras, more frames.
bool long_mode();
// `small` normally, `big` in the long mode.
template <typename T>
T pick(T small, T big) {
  return long_mode() ? big : small;
}

// Prints "[stress] <case> <metric>: worst=<value> bound=<bound>" to stdout (one line, flushed).
void report(const std::string& stress_case, const std::string& metric, double worst, double bound);

// The scene scaled about the origin by `scale`, then moved by `offset` (positions, node transforms, light
// positions and ranges), computed in double and rounded to float once.
Scene transform_scene(const Scene& scene, double scale, const glm::dvec3& offset);
// The same for a camera (position only; orientation and tangents are unchanged).
Camera transform_camera(const Camera& camera, double scale, const glm::dvec3& offset);

// Light bits (pixel x light) that differ; UINT64_MAX when the buffers differ in size or light count.
uint64_t differing_bits(const VisibilityBuffer& a, const VisibilityBuffer& b);
uint64_t total_bits(const VisibilityBuffer& v);
// Bits that differ and are not within one pixel of a place where the reference `a` changes that bit
// (shadow boundaries and silhouettes move by sub-pixel amounts under rounding).
uint64_t differing_bits_off_edges(const VisibilityBuffer& a, const VisibilityBuffer& b);

// Bookmark cameras and scene loading: the server tests' helpers (tests/server/test_scenes.hpp).
using test::bookmark_cameras;
using test::load_scene_or_fail;

// Tracer options for the tests: Embree with 2 threads; Vulkan on whatever device the environment gives
// (lavapipe under ctest).
server::TracerOptions embree_options(server::SkipOptions skip = {});
server::TracerOptions vulkan_options(server::SkipOptions skip = {});

// Builds a tracer of `backend` for the scene (embree_options / vulkan_options with `skip`) and traces one camera.
VisibilityBuffer trace_once(server::TracerBackend backend, const Scene& scene, const Camera& camera,
                            server::SkipOptions skip = {}, server::TraceStats* out_stats = nullptr);
const char* backend_label(server::TracerBackend backend);  // "embree" | "vulkan"

// Peak resident memory of this process (MiB).
double peak_rss_mib();

}  // namespace dhr::stress
