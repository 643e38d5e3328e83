// Deterministic synthetic visibility buffers for codec tests, benchmarks and the evaluation when no
// tracer is at hand. Same arguments -> same bytes on every platform (own PRNG, no <random> distributions).
#pragma once
#include "visibility/visibility.hpp"

#include <cstdint>

namespace dhr {

// Every pixel has `mask` (clipped to the light bits).
VisibilityBuffer make_uniform_visibility(uint32_t width, uint32_t height, uint32_t light_count, uint32_t mask);

// Independent random bits per pixel and light: the incompressible worst case.
VisibilityBuffer make_random_visibility(uint32_t width, uint32_t height, uint32_t light_count, uint64_t seed);

// Diagonal stripes, a different period and phase per light.
VisibilityBuffer make_stripe_visibility(uint32_t width, uint32_t height, uint32_t light_count, uint32_t period);

// 2D shadow-like blobs: per light, a few ellipses with wobbly edges where that light is blocked.
VisibilityBuffer make_blob_visibility(uint32_t width, uint32_t height, uint32_t light_count, uint64_t seed);

// Ray-traced toy room (floor, walls, ceiling, boxes and spheres on the floor, point lights near the
// ceiling), seen from eye height: bit i = light i reaches the surface (N.L > 0, in range, unoccluded).
// The closest synthetic stand-in for a real traced buffer (hard shadows, back-facing regions).
VisibilityBuffer make_room_visibility(uint32_t width, uint32_t height, uint32_t light_count, uint64_t seed);

}  // namespace dhr
