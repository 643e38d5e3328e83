// Which shadow-map faces a frame re-renders when the scene moves (DESIGN 8b: the headset's own maps are
// re-rendered when casters move). Per light with a map, a face is stale when
//   - the light moves (all faces: its map moved with it; a sun's tile is refitted), or
//   - a moving mesh's bounding sphere at the frame's scene time may cast into it: the sphere reaches into the
//     light's range (range 0: everywhere) and is not outside the face's frustum (sphere_may_be_visible on the
//     face camera; a sun's tile covers the whole scene, so any moving mesh), or
//   - the face held a moving caster when it was last rendered (the caster may have left: render it away once).
// Conservative: a spot light's cone is not tested, and a sphere bounds the mesh. A static scene has no stale face.
#pragma once
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>

#include "render/shadow_maps.hpp"
#include "scene/scene.hpp"

namespace dhr::render {

class ClientMotion;

// Bounding spheres of the scene's meshes at one scene time (world), one per ClientMesh.
struct MeshSpheres {
  std::span<const glm::dvec3> centre;
  std::span<const double> radius;
};

// Bit f (0-5; a sun: bit 0): whether face f of `tile`'s map may hold a moving mesh of `motion` at the spheres'
// time. 0 for a light without a map.
uint8_t faces_seeing_motion(const ShadowTile& tile, const SceneLight& light, const ClientMotion& motion,
                            const MeshSpheres& spheres, uint32_t face_size);

// The faces to re-render: every face of a moving light's map, else those that see a moving mesh now or held one.
uint8_t stale_faces(const ShadowTile& tile, bool light_moves, uint8_t seeing_now, uint8_t held);

}  // namespace dhr::render
