// The warp of soft levels (bilinear_warp.h's warp_vote_fields): on the area room (a rect and a sphere light with
// soft fields, one hard light) with a sun added, with level patterns in the soft fields, the 2x2 lookups blend the
// samples' levels where they differ. The deferred warp (G-buffer normals) equals the CPU reference on every pixel
// not within kMargin of a flip, the forward pass on all but a few (interpolated normals in its shadow-map lookups),
// and the blends are between the samples' levels: a blended field is never outside the range of the four around
// it. Where the four span more than kClientWarpSoftEdgeSpread levels (the pattern wraps from 7 to 0) the sun's
// field is an edge, which the shadow maps decide (the CPU reference's shadow lookup, which the deferred warp
// equals); the rect's and the sphere's keep the blend there too (soft_edge_light_mask).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "forward_test_frame.hpp"
#include "render/eye_pipeline.hpp"
#include "render/light_layout.hpp"
#include "render/shadow_maps.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using ClientWarpLevelsTest = vk::test::VulkanTest;
using namespace forward_test;

Scene area_room() {
  Scene scene = default_room_area();
  SceneLight sun;  // a disk sun, 45 degrees high: the one kind of soft light whose wide level spans are edges
  sun.type = SceneLight::Type::kDirectional;
  sun.name = "test sun";
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, -0.7f));
  sun.intensity = 2.0f;
  sun.angle = 0.0093f;
  scene.lights.push_back(sun);
  return scene;
}

VisibilityLayout g_layout;  // the area room's, set before the frame is made

// Levels in blocks of several pixels that step by one to three levels, and a blocky hard bit.
VisibilityBuffer levels(const Camera& traced, uint32_t) {
  return buffer_of_shares(traced, g_layout, [](uint32_t x, uint32_t y, uint32_t i) {
    return g_layout.is_soft(i) ? static_cast<float>(((x / 5) + (y / 4) * (i + 1)) % 8) / 7.0f
                               : static_cast<float>(((x / 8) + (y / 6)) % 2);
  });
}

TEST_F(ClientWarpLevelsTest, BlendsLevelsAsTheCpuReferenceDoes) {
  const Scene room = area_room();
  g_layout = layout_for_lights(room.lights);  // before the rig makes the frame's bits
  ASSERT_TRUE(g_layout.any_soft());
  SceneRig rig(ctx(), room, levels);
  const Scene& scene = rig.scene;
  const ClientScene& gpu_scene = rig.gpu_scene;
  ShadowMaps& maps = rig.maps;
  const ShadowReference& shadow = rig.shadow;
  const ForwardTestFrame& warp = rig.warp;
  const WarpSettings settings = WarpSettings::server_edges();
  const ForwardResult fwd = run_forward(ctx(), gpu_scene, ForwardMode::kServerEdges, warp.frame);

  EyePipeline deferred(ctx(), gpu_scene, kExtent, deferred_options(settings));
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { deferred.record(cmd, 0, warp.view, warp.input, {}, &maps); });
  const std::vector<uint32_t> deferred_mask = test::read_pixels<uint32_t>(ctx(), deferred.warp().mask);
  const std::vector<uint32_t> deferred_status = test::read_pixels<uint32_t>(ctx(), deferred.warp().status);

  const std::vector<glm::vec3> normals = test::read_normal_vectors(ctx(), deferred.gbuffer().normal);
  WarpInput in = warp.reference_input(fwd.depth);
  in.normals = normals;
  in.settings = settings;
  in.shadow = &shadow;
  const WarpResult cpu = warp_reference(in);

  size_t compared = 0, ambiguous = 0, deferred_wrong = 0, forward_wrong = 0, blended = 0, outside_range = 0, edges = 0,
         edges_not_blend = 0, wide_blended = 0;
  const uint32_t edge_lights = soft_edge_light_mask(scene.lights);
  for (size_t i = 0; i < fwd.depth.size(); ++i) {
    if (cpu.margin[i] < kMargin) {
      ++ambiguous;
      continue;
    }
    ++compared;
    const uint32_t status = static_cast<uint32_t>(cpu.status[i]);
    if ((deferred_status[i] & 0xFFu) != status || deferred_mask[i] != cpu.masks[i]) {
      if (++deferred_wrong <= 5) {
        ADD_FAILURE() << "pixel " << i % kExtent.width << "," << i / kExtent.width << ": deferred " << deferred_mask[i]
                      << ", cpu " << cpu.masks[i] << " (" << to_string(cpu.status[i]) << ")";
      }
    }
    forward_wrong += (fwd.status[i] & shader::kClientForwardStatusMask) != status || fwd.mask[i] != cpu.masks[i];
    if (cpu.status[i] != WarpStatus::kKnown) continue;
    // A soft field between the levels of the 2x2 samples around the lookup (the pattern's levels).
    const glm::dvec2 q = cpu.lookup[i] - glm::dvec2(0.5);
    const int a0 = static_cast<int>(std::floor(q.x)), b0 = static_cast<int>(std::floor(q.y));
    for (uint32_t l = 0; l < g_layout.light_count; ++l) {
      if (!g_layout.is_soft(l)) continue;
      float lo = 1.0f, hi = 0.0f;
      double blend = 0.0;
      const double fx = q.x - a0, fy = q.y - b0;
      for (int k = 0; k < 4; ++k) {
        const int a = std::clamp(a0 + (k & 1), 0, static_cast<int>(warp.buffer.width) - 1);
        const int b = std::clamp(b0 + (k >> 1), 0, static_cast<int>(warp.buffer.height) - 1);
        const float v = g_layout.visibility(warp.buffer.get(static_cast<uint32_t>(a), static_cast<uint32_t>(b)), l);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        blend += ((k & 1) != 0 ? fx : 1.0 - fx) * ((k >> 1) != 0 ? fy : 1.0 - fy) * static_cast<double>(v);
      }
      const float shown = g_layout.visibility(cpu.masks[i], l);
      const bool wide =
          std::lround((hi - lo) * (kDefaultSoftLevels - 1)) > static_cast<long>(shader::kClientWarpSoftEdgeSpread);
      if (wide && ((edge_lights >> l) & 1u) == 0) ++wide_blended;
      if (wide && ((edge_lights >> l) & 1u) != 0) {
        ++edges;
        // Not the blend (which a penumbra would show) wherever the shadow maps say another level.
        edges_not_blend += g_layout.with_visibility(0, l, static_cast<float>(blend)) !=
                           g_layout.with_visibility(0, l, shown);
        continue;
      }
      if (hi > lo && shown > lo && shown < hi) ++blended;
      if (shown < lo - 1e-6f || shown > hi + 1e-6f) ++outside_range;
    }
  }
  std::printf("soft levels: %zu compared, %zu ambiguous; %zu fields blended strictly between their samples (%zu over a "
              "wide span), %zu outside, %zu sun edges (%zu not the blend); %zu differ deferred, %zu forward\n",
              compared, ambiguous, blended, wide_blended, outside_range, edges, edges_not_blend, deferred_wrong,
              forward_wrong);
  EXPECT_EQ(deferred_wrong, 0u);
  EXPECT_LE(forward_wrong, compared / 200);
  EXPECT_LT(ambiguous, fwd.depth.size() / 5);
  EXPECT_GT(blended, compared / 20);  // the test means something: many lookups fall between different levels
  EXPECT_EQ(outside_range, 0u);
  EXPECT_EQ(edge_lights, 1u << (scene.lights.size() - 1));  // the sun alone
  EXPECT_GT(wide_blended, compared / 50);  // the rect's and the sphere's wide spans: blended, in range (above)
  EXPECT_GT(edges, compared / 50);  // and many of the sun's straddle an edge, which the shadow maps decide:
  EXPECT_GT(edges_not_blend, edges / 4);  // often another level than the blend
}

}  // namespace
}  // namespace dhr::render
