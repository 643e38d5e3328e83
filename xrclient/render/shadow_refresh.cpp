#include "render/shadow_refresh.hpp"

#include <glm/geometric.hpp>

#include "render/render_camera.hpp"
#include "render/client_motion.hpp"

namespace dhr::render {
namespace {

constexpr uint8_t kAllCubeFaces = 0x3f;

bool in_range(const SceneLight& light, const glm::dvec3& centre, double radius) {
  if (light.type == SceneLight::Type::kDirectional || !(light.range > 0.0f)) return true;
  return glm::length(centre - glm::dvec3(light.position)) - radius < static_cast<double>(light.range);
}

}  // namespace

uint8_t faces_seeing_motion(const ShadowTile& tile, const SceneLight& light, const ClientMotion& motion,
                            const MeshSpheres& spheres, uint32_t face_size) {
  if (!tile.row) return 0;
  uint8_t seen = 0;
  for (const uint32_t m : motion.moving_meshes()) {
    const glm::dvec3& c = spheres.centre[m];
    const double r = spheres.radius[m];
    if (tile.sun) {
      seen |= 1u;  // the tile covers the scene
      continue;
    }
    if (!in_range(light, c, r)) continue;
    for (uint32_t face = 0; face < 6; ++face) {
      if ((seen >> face) & 1u) continue;
      if (sphere_may_be_visible(cube_face_camera(tile.position, face, face_size), c, r)) seen |= uint8_t(1u << face);
    }
    if (seen == kAllCubeFaces) break;
  }
  return seen;
}

uint8_t stale_faces(const ShadowTile& tile, bool light_moves, uint8_t seeing_now, uint8_t held) {
  if (!tile.row) return 0;
  if (light_moves) return tile.sun ? uint8_t{1} : kAllCubeFaces;
  return static_cast<uint8_t>(seeing_now | held);
}

}  // namespace dhr::render
