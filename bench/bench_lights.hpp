// Many-light runs (issue 28, "Many lights"): point lights added to a scene, spread over its bounds below its top.
// codec_bench and trace_bench take them with --lights N [--light-range M].
#pragma once
#include <cstdint>

#include "scene/scene.hpp"

namespace dhr::bench {

// The range given to added lights when --light-range is not: none (infinite, as before light slots) while the scene
// keeps at most kMaxLights lights; beyond, the radius at which `total` spheres fill six times the volume the lights
// are spread over (a point of it is reached by about six of them on average), rounded to the centimetre.
double default_bench_light_range(const Scene& scene, uint32_t total);

// Adds point lights (20 cd, `range_m` metres, 0 = infinite) after the scene's own until it has `total`: positions
// from one seeded generator, the same for every run and machine; in the upper part of the bounds for at most
// kMaxLights lights, over 0.1-0.9 of each extent for more.
void add_bench_lights(Scene& scene, uint32_t total, double range_m);

}  // namespace dhr::bench
