// The shaded preview of a snapshot: what the client would show, from the traced visibility bits.
//   I = albedo / pi * sum_i bit_i * saturate(N.L_i) * E_i   (DESIGN.md), plus a faint ambient term so
// shadowed surfaces stay recognisable; auto exposure (95th percentile), Reinhard tonemap, sRGB.
#pragma once
#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "visibility/visibility.hpp"
#include "trace/embree/embree_scene.hpp"

#include <cstdint>
#include <vector>

namespace dhr::server::cli {

// RGB8 pixels of camera.extent. `embree` must be built from `scene` (same mesh order).
std::vector<uint8_t> shade_preview(const Scene& scene, const EmbreeScene& embree, const Camera& camera,
                                   const VisibilityBuffer& visibility);

// Linear base colour at a hit: material factor times its base-colour image (nearest texel, wrap modes).
glm::vec3 albedo_at(const Scene& scene, const SurfaceHit& hit);

}  // namespace dhr::server::cli
