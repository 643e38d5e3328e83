// The client's view of the visibility layout (visibility/visibility_layout.hpp) of a scene's lights, and what the
// GPU gets of it: the layout follows from which lights have an extent (SceneLight::has_extent), so the shaders
// get a mask of the soft lights (bit i: light i has a kSoftLevelBits-bit field; shaders/client/visibility_field.h
// derives the offsets from it) or, for the shadow lookup, each light's offset and width.
#pragma once
#include <cstdint>
#include <span>

#include "scene/scene.hpp"
#include "visibility/visibility_layout.hpp"

namespace dhr::render {

// The layout both ends derive from the lights (throws std::invalid_argument for more than kMaxLights).
VisibilityLayout layout_for_lights(std::span<const SceneLight> lights);

// Bit i: light i has a soft field. The GPU's running offsets (visibility_field.h) equal the layout's offsets.
uint32_t soft_light_mask(const VisibilityLayout& layout);

// Bit i: light i's soft field is decided by the shadow maps where the warp's 2x2 samples span more than
// kClientWarpSoftEdgeSpread levels (shaders/client/bilinear_warp.h): a sun's (a directional light with an angle),
// whose penumbra is a pixel or two wide. Other soft lights keep the samples' blend there.
uint32_t soft_edge_light_mask(std::span<const SceneLight> lights);

// The radius PCSS takes for a light with an extent (metres; 0: hard): a sphere light's radius; a rect's
// equal-area disk radius sqrt(width x height / pi); a disk's width / 2. A sun (directional with an angle, its
// angular diameter) has no length: tan(angle / 2), the tangent of its angular radius (penumbra half-width per
// metre between blocker and receiver).
double pcss_light_radius(const SceneLight& light);

}  // namespace dhr::render
