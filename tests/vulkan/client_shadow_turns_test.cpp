// Shadow maps that take turns (render::ShadowRefresh, issue 27): where DHR's maps only fill, each light's map in a
// moving scene is re-rendered once per period of scene time at its own phase, with every face that went stale since;
// in between it stays as it was rendered, origin included. At its turn a light's map is bit for bit the map an
// every-frame re-render has then; between turns a moving light's is not. The frame's pipeline takes turns only while
// both eyes show visibility traced for the scene time shown. Scene: tests/vulkan/moving_scene.hpp (light A sees the
// moving occluder, B is out of its range, C moves).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

#include "client_test_helpers.hpp"
#include "forward_test_frame.hpp"
#include "frame/stereo_pipeline.hpp"
#include "moving_scene.hpp"
#include "render/client_motion.hpp"
#include "render/client_scene.hpp"
#include "render/render_camera.hpp"
#include "render/shadow_maps.hpp"
#include "scene/scene_at.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using ClientShadowTurnsTest = vk::test::VulkanTest;

constexpr uint32_t kFace = 64;
constexpr int64_t kMs = 1'000'000;
constexpr int64_t kPeriod = 30 * kMs;  // three lights: phases 0, 10 and 20 ms

ShadowUpdate update_at(vk::Context& ctx, const ClientScene& gpu, ShadowMaps& maps, int64_t t, int64_t period) {
  MovedScene moved;
  gpu.motion().sample(scene_seconds(t), gpu.meshes(), moved);
  ShadowUpdate out;
  ctx.submit_and_wait([&](VkCommandBuffer cmd) { out = maps.update(cmd, moved, ShadowRefresh{t, period, false}); });
  return out;
}

// Light `l`'s row of the atlas (six faces), read back.
std::vector<float> light_row(const vk::Context& ctx, const ShadowMaps& maps, uint32_t l) {
  std::vector<float> atlas;
  forward_test::shadow_reference(ctx, maps, atlas);
  const size_t row = size_t{6} * kFace * kFace;
  const uint32_t at = *maps.tiles()[l].row;
  return std::vector<float>(atlas.begin() + static_cast<ptrdiff_t>(at * row),
                            atlas.begin() + static_cast<ptrdiff_t>((at + 1) * row));
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST_F(ClientShadowTurnsTest, EachLightIsReRenderedOncePerPeriodAtItsPhase) {
  const Scene scene = moving_scene();
  const ClientScene gpu(ctx(), scene);
  ShadowMaps maps(ctx(), gpu, ShadowMapSettings{.size = kFace});
  std::array<std::vector<int64_t>, 3> turns;  // per light: the scene times it was re-rendered at
  glm::dvec3 c_rendered_at = maps.tiles()[2].position;
  for (int64_t t = 5 * kMs; t <= 95 * kMs; t += 5 * kMs) {
    const ShadowUpdate u = update_at(ctx(), gpu, maps, t, kPeriod);
    uint32_t lights = 0;
    for (uint32_t l = 0; l < 3; ++l) {
      if (maps.updated_faces()[l] == 0) continue;
      turns[l].push_back(t);
      ++lights;
    }
    EXPECT_EQ(u.lights, lights) << "t = " << t / kMs << " ms";
    if (maps.updated_faces()[2] != 0) {
      EXPECT_EQ(maps.updated_faces()[2], 0x3fu) << "C moves: all of its faces at its turn";
      c_rendered_at = glm::dvec3(light_at(scene, scene.lights[2], scene_seconds(t)).position);
    }
    EXPECT_EQ(maps.tiles()[2].position, c_rendered_at) << "C's map stays where it was rendered, t = " << t / kMs;
    const ShadowUpdate again = update_at(ctx(), gpu, maps, t, kPeriod);
    EXPECT_EQ(again.faces, 0u) << "the same scene time again: no light's turn, t = " << t / kMs << " ms";
  }
  // The first update is every light's turn; then light l's come when (t + l * 10 ms) / 30 ms crosses an integer.
  EXPECT_EQ(turns[0], (std::vector<int64_t>{5 * kMs, 30 * kMs, 60 * kMs, 90 * kMs})) << "A sees the occluder";
  EXPECT_TRUE(turns[1].empty()) << "B's range does not reach the occluder: never stale";
  EXPECT_EQ(turns[2], (std::vector<int64_t>{5 * kMs, 10 * kMs, 40 * kMs, 70 * kMs})) << "C";
  // Without a period every stale face is re-rendered at every new time (`local`).
  const ShadowUpdate every = update_at(ctx(), gpu, maps, 97 * kMs, 0);
  EXPECT_EQ(every.lights, 2u);
}

TEST_F(ClientShadowTurnsTest, AtItsTurnALightsMapIsTheEveryFrameMap) {
  const Scene scene = moving_scene();
  const ClientScene gpu(ctx(), scene);
  ShadowMaps turns(ctx(), gpu, ShadowMapSettings{.size = kFace});
  ShadowMaps every(ctx(), gpu, ShadowMapSettings{.size = kFace});
  size_t compared = 0, older = 0;
  for (int64_t t = 5 * kMs; t <= 65 * kMs; t += 5 * kMs) {
    update_at(ctx(), gpu, turns, t, kPeriod);
    update_at(ctx(), gpu, every, t, 0);
    for (const uint32_t l : {0u, 2u}) {
      const bool same = same_bits(light_row(ctx(), turns, l), light_row(ctx(), every, l));
      if (turns.updated_faces()[l] != 0) {
        EXPECT_TRUE(same) << "light " << l << " at its turn, t = " << t / kMs << " ms";
        ++compared;
      } else if (l == 2) {
        older += same ? 0 : 1;
      }
    }
  }
  EXPECT_GE(compared, 6u);
  EXPECT_GT(older, 0u) << "between its turns the moving light's map is an older one";
}

// The pipeline takes turns while both eyes show visibility traced for the scene time shown (a second frame within
// C's period re-renders nothing of it); an eye without visibility, or with visibility traced for another scene time,
// makes it re-render every stale face (the maps then shade what moved), and the turns go on from there.
TEST_F(ClientShadowTurnsTest, StereoPipelineTakesTurnsOnlyWhileTheMapsOnlyFill) {
  const Scene scene = moving_scene();
  const ClientScene gpu(ctx(), scene);
  EyePipelineOptions options;
  options.frames_in_flight = 1;
  options.warp = WarpSettings::server_edges();
  constexpr Extent kExtent{48, 36};
  client::StereoPipeline stereo(ctx(), gpu, kExtent, options,
                                ShadowMapSettings{.size = kFace, .fill_period_ns = kPeriod});
  const Camera camera = display_camera(camera_view(), kExtent);
  VisibilityBuffer lit = VisibilityBuffer::create(kExtent.width, kExtent.height, 3);
  for (size_t i = 0; i < lit.pixel_count(); ++i) lit.set_mask_at(i, 0x7u);
  const auto frame = [&](int64_t shown, std::array<int64_t, 2> traced, bool visibility) {
    client::StereoInputs inputs;
    inputs.views = {camera_view(), camera_view()};
    inputs.scene_time_ns = shown;
    for (uint32_t e = 0; e < 2; ++e) {
      if (!visibility) continue;
      inputs.visibility[e].buffer = &lit;
      inputs.visibility[e].traced = camera;
      inputs.visibility[e].scene_time_ns = traced[e];
    }
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { stereo.record(cmd, 0, inputs); });
    return stereo.read_stats(0)[0].shadow_update;
  };
  EXPECT_EQ(frame(5 * kMs, {5 * kMs, 5 * kMs}, true).lights, 2u) << "the first frame: every light's turn";
  EXPECT_EQ(frame(6 * kMs, {6 * kMs, 6 * kMs}, true).lights, 0u) << "no light's turn yet";
  EXPECT_EQ(frame(7 * kMs, {7 * kMs, 6 * kMs}, true).lights, 2u) << "eye 1 shows visibility of another time";
  EXPECT_EQ(frame(8 * kMs, {8 * kMs, 8 * kMs}, false).lights, 2u) << "no visibility: the maps shade everything";
  EXPECT_EQ(frame(9 * kMs, {9 * kMs, 9 * kMs}, true).lights, 0u) << "the turns go on from the last frame's";
  EXPECT_EQ(frame(10 * kMs, {10 * kMs, 10 * kMs}, true).lights, 1u) << "C's turn (phase 20 ms of 30)";
}

}  // namespace
}  // namespace dhr::render
