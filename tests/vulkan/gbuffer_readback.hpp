// One G-buffer pass recorded and read back (client_gbuffer_test, client_motion_test).
#pragma once
#include <cstdint>
#include <vector>

#include "client_test_helpers.hpp"
#include "math/projection.hpp"
#include "render/client_motion.hpp"
#include "render/client_scene.hpp"
#include "render/gbuffer_pass.hpp"

namespace dhr::render::test {

struct GBufferReadback {
  std::vector<float> depth;
  std::vector<float> normal;    // 4 per pixel
  std::vector<uint8_t> albedo;  // 4 per pixel
};

// Renders `scene` (moving meshes where `moved` puts them; null: at rest) from `camera` and reads the three images back.
inline GBufferReadback render_gbuffer(vk::Context& ctx, const ClientScene& scene, const Camera& camera, double near,
                                      const MovedScene* moved = nullptr) {
  const GBufferPass pass(ctx, scene);
  GBuffer targets = GBuffer::create(ctx, camera.extent);
  ctx.submit_and_wait([&](VkCommandBuffer cmd) { pass.record(cmd, targets, camera, near, moved); });
  return GBufferReadback{read_pixels<float>(ctx, targets.depth), read_normals(ctx, targets.normal),
                         read_pixels<uint8_t>(ctx, targets.albedo, 4)};
}

}  // namespace dhr::render::test
