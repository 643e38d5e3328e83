// A sun's shadow map (a directional light with an angle, a soft light): one orthographic size x size tile fitted to
// the scene's bounds, looking along the light, in column 0 of the light's atlas row (shadow_maps.hpp). Stored
// depth 1 - distance / depth_range from the near plane through `position` (reversed: 0 = nothing), so the
// G-buffer pipeline (compare GREATER, cleared to 0) renders it. GLSL twin: shaders/client/shadow_texel.h.
#pragma once
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "render/shadow_maps.hpp"
#include "scene/scene.hpp"

namespace dhr::render {

// The tile's frame: sphere of the bounds (centre c, radius r) grown by a margin m = r / 100 + 1 mm; the near
// plane is r + m before c along the light, the side and the depth range 2 (r + m).
SunMap fit_sun_map(const SceneBounds& bounds, const glm::dvec3& direction);

// The camera-relative view-projection (applied to p - position) that renders the tile.
glm::dmat4 sun_view_projection(const SunMap& sun);

// Where v (a point relative to `position`) falls in the tile (face 0; distance from the near plane); margin as
// cube_lookup's.
CubeLookup sun_lookup(const SunMap& sun, const glm::dvec3& v, uint32_t size);

}  // namespace dhr::render
