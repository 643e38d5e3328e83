#include "scene/scene_hash.hpp"

#include <cstring>

namespace dhr {
namespace {

class Fnv1a {
 public:
  void bytes(const void* data, size_t size) {
    const auto* p = static_cast<const uint8_t*>(data);
    for (size_t i = 0; i < size; ++i) {
      hash_ ^= p[i];
      hash_ *= 0x100000001b3ull;
    }
  }
  void u32(uint32_t v) {
    const uint8_t le[4] = {static_cast<uint8_t>(v), static_cast<uint8_t>(v >> 8), static_cast<uint8_t>(v >> 16),
                           static_cast<uint8_t>(v >> 24)};
    bytes(le, 4);
  }
  void u64(uint64_t v) {
    u32(static_cast<uint32_t>(v));
    u32(static_cast<uint32_t>(v >> 32));
  }
  void f32(float v) {
    uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    u32(bits);
  }
  void vec3(const glm::vec3& v) {
    f32(v.x);
    f32(v.y);
    f32(v.z);
  }
  uint64_t value() const { return hash_; }

 private:
  uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace

uint64_t scene_content_hash(const Scene& scene) {
  Fnv1a h;
  h.u64(scene.meshes.size());
  for (const SceneMesh& mesh : scene.meshes) {
    h.u64(mesh.positions.size());
    for (const glm::vec3& p : mesh.positions) h.vec3(p);
    h.u64(mesh.indices.size());
    for (uint32_t i : mesh.indices) h.u32(i);
  }
  h.u64(scene.lights.size());
  for (const SceneLight& light : scene.lights) {
    h.u32(static_cast<uint32_t>(light.type));
    h.vec3(light.position);
    h.vec3(light.direction);
    h.vec3(light.color);
    h.f32(light.intensity);
    h.f32(light.range);
    h.f32(light.inner_cone);
    h.f32(light.outer_cone);
    // Only lights with an extent hash it, so scenes of punctual lights keep the hash they always had (a client
    // and a server of different versions still agree on them).
    if (light.has_extent()) {
      h.f32(light.radius);
      h.f32(light.angle);
      h.f32(light.width);
      h.f32(light.height);
      h.vec3(light.tangent);
      h.vec3(light.bitangent);
    }
  }
  return h.value();
}

}  // namespace dhr
