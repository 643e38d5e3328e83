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
  void f64(double v) {
    uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    u64(bits);
  }
  void dmat4(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) f64(m[c][r]);
    }
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

// Everything sampling reads. Only called for a scene with animation tracks, so static scenes keep their hash.
void hash_animation(Fnv1a& h, const SceneAnimation& animation) {
  h.u64(animation.clips.size());
  for (const AnimationClip& clip : animation.clips) h.f64(clip.duration);
  h.u64(animation.nodes.size());
  for (const AnimatedNode& n : animation.nodes) {
    h.u32(n.node);
    h.u32(n.parent);
    h.dmat4(n.parent_rest_world);
    for (int i = 0; i < 3; ++i) h.f64(n.translation[i]);
    for (int i = 0; i < 4; ++i) h.f64(n.rotation[i]);
    for (int i = 0; i < 3; ++i) h.f64(n.scale[i]);
    h.dmat4(n.rest_local);
    h.dmat4(n.rest_world);
    h.u32(n.first_track);
    h.u32(n.track_count);
  }
  h.u64(animation.tracks.size());
  for (const AnimationTrack& t : animation.tracks) {
    h.u32(t.animation);
    h.u32(t.node);
    h.u32(static_cast<uint32_t>(t.path));
    h.u32(static_cast<uint32_t>(t.interpolation));
    h.u64(t.times.size());
    for (float v : t.times) h.f32(v);
    h.u64(t.values.size());
    for (float v : t.values) h.f32(v);
  }
}

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
  if (!scene.animation.empty()) {
    // Which lights follow which node decides where they are at a time; static scenes hash neither.
    for (const SceneLight& light : scene.lights) h.u32(light.node);
    hash_animation(h, scene.animation);
  }
  return h.value();
}

}  // namespace dhr
