// The scene hash a Welcome carries: 64-bit FNV-1a over what the tracer sees (world-space triangle
// positions and indices, mesh by mesh, and every light's parameters), so a client can tell that the
// server traces the content it rasterizes: dhr-server sends the hash of its session scene
// (scene/session_scene.hpp, --lights applied) and dhr-xrclient refuses a Welcome that names another than its
// own. Any field a light gains (its shape, its extent) must be hashed here too. A scene with animation tracks
// also hashes its animation data and each light's node; a static scene hashes exactly what it did before. Not cryptographic; deterministic across runs and machines
// (little-endian IEEE bit patterns, no pointers, no hashing of names or materials).
#pragma once
#include "scene/scene.hpp"

#include <cstdint>

namespace dhr {

uint64_t scene_content_hash(const Scene& scene);

}  // namespace dhr
