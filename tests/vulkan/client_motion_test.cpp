// A moving scene on the client (issue 27, DESIGN 5b / 8b): every raster pass draws a moving mesh with its motion at
// the frame's scene time, so the G-buffer of the scene at time t equals that of scene_at(scene, t) rendered
// statically; static meshes keep their bits; the shadow maps re-render exactly the lights that moving casters or
// their own motion made stale, and after the occluder moved a lookup at a floor point says what a CPU ray against
// scene_at says. Scenes are built in code: a static floor, a small occluder on an animated node (translated and
// turned), three point lights (one near, one out of range, one moving).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <span>
#include <vector>

#include "client_test_helpers.hpp"
#include "forward_test_frame.hpp"
#include "frame/stereo_pipeline.hpp"
#include "render/client_scene.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/render_camera.hpp"
#include "render/client_motion.hpp"
#include "render/shadow_maps.hpp"
#include "scene/node_overrides.hpp"
#include "scene/scene_at.hpp"
#include "gbuffer_readback.hpp"
#include "moving_scene.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using ClientMotionTest = vk::test::VulkanTest;

constexpr Extent kExtent{96, 72};
constexpr double kNear = kDefaultNearPlane;
using Readback = test::GBufferReadback;

Readback render_gbuffer(vk::Context& ctx, const ClientScene& scene, const MovedScene* moved) {
  return test::render_gbuffer(ctx, scene, display_camera(camera_view(), kExtent), kNear, moved);
}

TEST_F(ClientMotionTest, MotionIsExposedPerMeshAndLight) {
  const Scene scene = moving_scene();
  const ClientScene gpu(ctx(), scene);
  const ClientMotion& motion = gpu.motion();
  ASSERT_TRUE(motion.animated());
  EXPECT_FALSE(motion.mesh_moves(0));
  EXPECT_TRUE(motion.mesh_moves(1));
  EXPECT_EQ(motion.moving_meshes(), std::vector<uint32_t>{1});
  EXPECT_EQ(motion.moving_lights(), std::vector<uint32_t>{2});
  const WorldBox rest = motion.rest_local_bounds(1);  // local frame: the node sits at (0, 1, 0)
  EXPECT_NEAR(rest.min.x, -0.2, 1e-6);
  EXPECT_NEAR(rest.max.y, 0.0, 1e-6);
  const WorldBox at1 = motion.world_bounds_at(1, 1.0);  // x + 1, turned 30 degrees about +z
  const Scene exact = scene_at(scene, 1.0);
  for (const glm::vec3& p : exact.meshes[1].positions) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(p[k], at1.min[k] - 1e-6);
      EXPECT_LE(p[k], at1.max[k] + 1e-6);
    }
  }
  MovedScene moved;
  motion.sample(1.0, gpu.meshes(), moved);
  EXPECT_EQ(moved.lights[2].position, exact.lights[2].position);
  EXPECT_EQ(moved.lights[0].position, scene.lights[0].position);
}

// The moved G-buffer equals scene_at's: depth within 1e-5 relative and normals within 2e-3 (both paths round
// differently: the motion in double into one float model-view-projection against moved float vertices; normals
// turned by a float normal matrix against moved_normal, stored as half floats), coverage alike but for pixel
// centres within rounding of an edge.
TEST_F(ClientMotionTest, MovingSceneAtTimeEqualsSceneAtRenderedStatically) {
  const Scene scene = moving_scene();
  const ClientScene gpu(ctx(), scene);
  for (const double t : {0.5, 1.3}) {
    MovedScene moved;
    gpu.motion().sample(t, gpu.meshes(), moved);
    const Readback a = render_gbuffer(ctx(), gpu, &moved);
    const Scene exact = scene_at(scene, t);
    const ClientScene gpu_exact(ctx(), exact);
    const Readback b = render_gbuffer(ctx(), gpu_exact, nullptr);
    size_t coverage = 0, occluder_pixels = 0;
    for (size_t i = 0; i < a.depth.size(); ++i) {
      if ((a.depth[i] > 0.0f) != (b.depth[i] > 0.0f)) {
        ++coverage;
        continue;
      }
      if (a.depth[i] == 0.0f) continue;
      EXPECT_NEAR(a.depth[i], b.depth[i], 1e-5 * static_cast<double>(b.depth[i])) << "pixel " << i;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.normal[i * 4 + k], b.normal[i * 4 + k], 2e-3) << "pixel " << i;
      occluder_pixels += std::abs(a.normal[i * 4 + 1] - 1.0f) > 0.01f ? 1 : 0;  // the turned occluder
    }
    EXPECT_LE(coverage, 4u);
    EXPECT_GT(occluder_pixels, 50u) << "the occluder is on screen at t = " << t;
  }
}

// An app-moved node (docs/motion.md, "App-moved nodes"): sampled with the app's transforms, the occluder is drawn
// where scene_at puts it with the same transforms (overriding its animation), not where the animation has it.
TEST_F(ClientMotionTest, AnAppMovedNodeIsDrawnWhereTheAppPutIt) {
  const Scene scene = moving_scene();
  const ClientScene gpu(ctx(), scene);
  NodeOverrides overrides;
  const Trs app{glm::dvec3(-0.6, 1.0, 0.2), glm::angleAxis(0.4, glm::dvec3(1.0, 0.0, 0.0)), glm::dvec3(1.5)};
  ASSERT_EQ(overrides.add(scene.animation, kOccluderNode, 250'000'000, app), NodeTransformVerdict::kAccepted);
  const double t = 0.5;
  MovedScene moved;
  gpu.motion().sample(t, gpu.meshes(), moved, &overrides);
  EXPECT_EQ(moved.overrides, &overrides);  // the warp's motion rule reads them from the frame's sample
  const Readback a = render_gbuffer(ctx(), gpu, &moved);
  const ClientScene gpu_exact(ctx(), scene_at(scene, t, &overrides));
  const Readback b = render_gbuffer(ctx(), gpu_exact, nullptr);
  MovedScene animated;
  gpu.motion().sample(t, gpu.meshes(), animated);
  const Readback c = render_gbuffer(ctx(), gpu, &animated);
  size_t coverage = 0, differs_from_animation = 0;
  for (size_t i = 0; i < a.depth.size(); ++i) {
    if ((a.depth[i] > 0.0f) != (b.depth[i] > 0.0f)) {
      ++coverage;
      continue;
    }
    if (a.depth[i] != 0.0f) {
      EXPECT_NEAR(a.depth[i], b.depth[i], 1e-5 * static_cast<double>(b.depth[i])) << "pixel " << i;
    }
    differs_from_animation += a.depth[i] != c.depth[i] ? 1 : 0;
  }
  EXPECT_LE(coverage, 4u);
  EXPECT_GT(differs_from_animation, 50u);
}

// Static meshes keep their bits whether or not the frame carries a MovedScene (only an off-screen mesh moves).
TEST_F(ClientMotionTest, StaticMeshesRenderTheSameBitsWithMotion) {
  const Scene scene = moving_scene(/*far_mover=*/true);
  const ClientScene gpu(ctx(), scene);
  ASSERT_TRUE(gpu.motion().mesh_moves(2));
  MovedScene moved;
  gpu.motion().sample(1.0, gpu.meshes(), moved);
  const Readback a = render_gbuffer(ctx(), gpu, nullptr);
  const Readback b = render_gbuffer(ctx(), gpu, &moved);
  ASSERT_EQ(a.depth.size(), b.depth.size());
  EXPECT_EQ(std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.normal.data(), b.normal.data(), a.normal.size() * sizeof(float)), 0);
  EXPECT_EQ(a.albedo, b.albedo);
}

// moving_scene() uploaded, with its shadow maps (faces of `size` texels) rendered at rest.
struct MovingMaps {
  Scene scene;
  ClientScene gpu;
  ShadowMaps maps;
  MovingMaps(const vk::Context& ctx, uint32_t size)
      : scene(moving_scene()), gpu(ctx, scene), maps(ctx, gpu, ShadowMapSettings{.size = size}) {}
};

TEST_F(ClientMotionTest, ShadowMapsReRenderWhatMotionMadeStale) {
  MovingMaps m(ctx(), 128);
  const Scene& scene = m.scene;
  const ClientScene& gpu = m.gpu;
  ShadowMaps& maps = m.maps;
  MovedScene moved;
  gpu.motion().sample(1.0, gpu.meshes(), moved);
  ShadowUpdate update;
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { update = maps.update(cmd, moved); });
  const std::vector<uint8_t>& faces = maps.updated_faces();
  ASSERT_EQ(faces.size(), 3u);
  EXPECT_NE(faces[0], 0u) << "A sees the moving occluder";
  EXPECT_EQ(faces[0] & (1u << 3), 1u << 3) << "A's -Y face looks at it";
  EXPECT_EQ(faces[1], 0u) << "B's range does not reach it";
  EXPECT_EQ(faces[2], 0x3fu) << "C moves";
  EXPECT_EQ(update.lights, 2u);
  EXPECT_EQ(maps.tiles()[2].position, glm::dvec3(moved.lights[2].position));

  // A static scene (the same without its animation) never re-renders.
  Scene still = scene;
  still.animation = SceneAnimation{};
  const ClientScene gpu_still(ctx(), still);
  ShadowMaps still_maps(ctx(), gpu_still, ShadowMapSettings{.size = 128});
  MovedScene still_moved;
  gpu_still.motion().sample(1.0, gpu_still.meshes(), still_moved);
  ShadowUpdate none{7, 7};
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { none = still_maps.update(cmd, still_moved); });
  EXPECT_EQ(none.lights, 0u);
  EXPECT_EQ(none.faces, 0u);
}

// The static casters' atlas plus the moving meshes gives the same depths as re-rendering every caster: the atlases
// of split and unsplit maps are equal bit for bit after each update (light C moves: its faces are re-rendered whole
// either way; A's faces that see the occluder are completed from the static atlas).
TEST_F(ClientMotionTest, SplitStaticCastersGiveTheSameMapsAsAFullReRender) {
  const Scene scene = moving_scene();
  const ClientScene gpu(ctx(), scene);
  ShadowMaps split(ctx(), gpu, ShadowMapSettings{.size = 128});
  ShadowMaps whole(ctx(), gpu, ShadowMapSettings{.size = 128, .split_static = false});
  MovedScene moved;
  for (const double t : {0.5, 1.0, 1.7, 0.0}) {
    gpu.motion().sample(t, gpu.meshes(), moved);
    ShadowUpdate a, b;
    ctx().submit_and_wait([&](VkCommandBuffer cmd) {
      a = split.update(cmd, moved);
      b = whole.update(cmd, moved);
    });
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_GT(a.faces, 6u) << "t = " << t << ": C's six faces and some of A's";
    std::vector<float> sa, sb;
    const ShadowReference ra = forward_test::shadow_reference(ctx(), split, sa);
    const ShadowReference rb = forward_test::shadow_reference(ctx(), whole, sb);
    ASSERT_EQ(sa.size(), sb.size());
    size_t differing = 0;
    for (size_t i = 0; i < sa.size(); ++i) differing += std::memcmp(&sa[i], &sb[i], sizeof(float)) != 0;
    EXPECT_EQ(differing, 0u) << "t = " << t;
  }
}

// Under the occluder at rest / where its shadow falls at t = 1 (x in [1.2, 1.8] from A): the maps' lookup
// (CPU reference on the read-back atlas) of light A flips as a CPU ray against scene_at says, at rest and after
// update() at t = 1; and again once the occluder has left (t = 0 rest pose: back in place).
TEST_F(ClientMotionTest, ShadowLookupFollowsTheMovedOccluder) {
  MovingMaps m(ctx(), 256);
  const Scene& scene = m.scene;
  const ClientScene& gpu = m.gpu;
  ShadowMaps& maps = m.maps;
  const std::vector<glm::dvec3> points = {{0.0, 0.0, 0.0}, {1.5, 0.0, 0.0}, {-1.0, 0.0, 0.5}};
  const glm::dvec3 up(0.0, 1.0, 0.0);
  auto check = [&](const Scene& exact, std::span<const SceneLight> lights, const char* when) {
    std::vector<float> storage;
    const ShadowReference ref = forward_test::shadow_reference(ctx(), maps, storage);
    for (const glm::dvec3& p : points) {
      const ShadowDecision d = shadow_mask_reference(ref, lights, p, up, 0.01);
      const bool lit = (d.mask & 1u) != 0;
      EXPECT_EQ(lit, !occluded(exact, p, glm::dvec3(lights[0].position)))
          << when << ": floor point " << p.x << ", " << p.z;
    }
  };
  check(scene, scene.lights, "rest");
  EXPECT_TRUE(occluded(scene, points[0], glm::dvec3(0, 3, 0)));
  MovedScene moved;
  for (const double t : {1.0, 0.0}) {
    gpu.motion().sample(t, gpu.meshes(), moved);
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { maps.update(cmd, moved); });
    const Scene exact = scene_at(scene, t);
    check(exact, moved.lights, t == 1.0 ? "t = 1" : "t = 0");
    if (t == 1.0) {
      EXPECT_FALSE(occluded(exact, points[0], glm::dvec3(0, 3, 0)));
      EXPECT_TRUE(occluded(exact, points[1], glm::dvec3(0, 3, 0)));
    }
  }
}

// The frame's pipeline samples the scene at StereoInputs::scene_time_ns, shades with the moved lights and reports
// the shadow-map re-render it recorded into the frame's command buffer in eye 0's stats; a static scene none.
TEST_F(ClientMotionTest, StereoPipelineReRendersAndReportsPerFrame) {
  for (const bool animated : {true, false}) {
    Scene scene = moving_scene();
    if (!animated) scene.animation = SceneAnimation{};
    const ClientScene gpu(ctx(), scene);
    EyePipelineOptions options;
    options.frames_in_flight = 1;
    options.warp = WarpSettings::server_edges();  // looks the shadow maps up
    client::StereoPipeline stereo(ctx(), gpu, kExtent, options);
    client::StereoInputs inputs;
    inputs.views = {camera_view(), camera_view()};
    inputs.scene_time_ns = 1'000'000'000;
    for (int frame = 0; frame < 2; ++frame) {
      ctx().submit_and_wait([&](VkCommandBuffer cmd) { stereo.record(cmd, 0, inputs); });
      const std::array<EyeStats, 2> stats = stereo.read_stats(0);
      EXPECT_EQ(stats[1].shadow_update.faces, 0u);
      if (!animated) {
        EXPECT_EQ(stats[0].shadow_update.faces, 0u);
        EXPECT_EQ(stats[0].gpu.shadow_update_ms, 0.0);
        EXPECT_FALSE(stereo.moved_scene().sampled);
        continue;
      }
      EXPECT_EQ(stats[0].shadow_update.lights, 2u) << "A (the occluder) and C (moving), frame " << frame;
      if (stats[0].gpu.valid) {
        EXPECT_GT(stats[0].gpu.shadow_update_ms, 0.0);
      }
      EXPECT_EQ(stereo.moved_scene().lights[2].position, light_at(scene, scene.lights[2], 1.0).position);
    }
  }
}

}  // namespace
}  // namespace dhr::render
