// client_bench with more than 32 lights (light slots, docs/server.md "Light slots"): the client's shadow maps hold
// at most 32 lights, so there is no `local` and no shipped (`--warp edges`) configuration; measured are the
// unshadowed forward render, clustered by the slots' grid (forward_ms), and DHR's deferred path, which the eye
// pipeline takes with light slots (dhr_deferred_ms), with the warp dhr-xrclient ships for such a scene (its shipped
// warp without shadow maps: the fields blended by the bilinear vote).
#pragma once
#include <cstdint>
#include <string>

#include "math/projection.hpp"
#include "plan/visibility_input.hpp"
#include "scene/scene.hpp"

namespace dhr::bench {

// Prints the JSON object (the last stdout line) and returns the exit code.
int run_many_lights(const std::string& scene_path, const Scene& scene, Extent size, const View& view,
                    const VisibilityInput& input, uint32_t warmup, uint32_t frames);

}  // namespace dhr::bench
