// The scene hash a Welcome carries: 64-bit FNV-1a over what the tracer sees (world-space triangle
// positions and indices, mesh by mesh, and every light's parameters), so a client can tell that the
// server traces the content it rasterizes. Not cryptographic; deterministic across runs and machines
// (little-endian IEEE bit patterns, no pointers, no hashing of names or materials).
#pragma once
#include "scene/scene.hpp"

#include <cstdint>

namespace dhr::server {

uint64_t scene_content_hash(const Scene& scene);

}  // namespace dhr::server
