// Shading pass: the output equals a CPU evaluation of I = albedo/pi * sum k_i saturate(N.L_i) E_i (with the
// shared light_eval.h math and display encoding) within 1/255 per channel; debug views select what they say.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "client_test_helpers.hpp"
#include "scene/lighting.hpp"
#include "metrics/visibility_synthetic.hpp"
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/forward_pass.hpp"
#include "render/gbuffer_pass.hpp"
#include "render/light_layout.hpp"
#include "render/warp_pass.hpp"
#include "render/render_camera.hpp"
#include "render/shading_pass.hpp"
#include "scene/light_slots.hpp"
#include "shaders/display_encode.h"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

using ClientShadingTest = vk::test::VulkanTest;

constexpr Extent kExtent{96, 72};
constexpr GuardBand kGuard{4, 3};
constexpr double kNear = kDefaultNearPlane;

// A floor and a back wall with different albedos, lit by a point, a spot and a directional light.
Scene lit_room() {
  Scene scene;
  scene.materials.push_back(test::colour_material({0.8f, 0.7f, 0.6f, 1.0f}));
  scene.materials.push_back(test::colour_material({0.3f, 0.5f, 0.9f, 1.0f}));
  scene.meshes.push_back(test::quad_mesh({-4, 0, 1}, {4, 0, 1}, {4, 0, -6}, {-4, 0, -6}, 0));
  scene.meshes.push_back(test::quad_mesh({-4, 0, -6}, {4, 0, -6}, {4, 4, -6}, {-4, 4, -6}, 1));
  SceneLight point;
  point.type = SceneLight::Type::kPoint;
  point.position = {-0.5f, 2.5f, -2.5f};
  point.color = {1.0f, 0.9f, 0.8f};
  point.intensity = 8.0f;
  point.range = 7.0f;
  SceneLight spot;
  spot.type = SceneLight::Type::kSpot;
  spot.position = {1.5f, 2.0f, -0.5f};
  spot.direction = glm::normalize(glm::vec3(-1.5f, -2.0f, -3.0f));
  spot.color = {0.6f, 0.8f, 1.0f};
  spot.intensity = 15.0f;
  spot.inner_cone = 0.25f;
  spot.outer_cone = 0.5f;
  SceneLight sun;
  sun.type = SceneLight::Type::kDirectional;
  sun.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.5f));
  sun.color = {1.0f, 0.95f, 0.9f};
  sun.intensity = 1.5f;
  scene.lights = {point, spot, sun};
  test::finish_scene(scene);
  return scene;
}

// lit_room with a rect light tilted towards +X (the room's left part is behind it: no light there) and a disk
// facing down instead of the spot and the sun.
Scene area_lit_room() {
  Scene scene = lit_room();
  SceneLight rect;
  rect.type = SceneLight::Type::kRect;
  rect.position = {0.0f, 1.5f, -3.0f};
  rect.direction = glm::normalize(glm::vec3(1.0f, -0.5f, 0.0f));
  rect.tangent = {0.0f, 0.0f, 1.0f};
  rect.bitangent = glm::cross(rect.tangent, rect.direction);
  rect.color = {1.0f, 0.9f, 0.7f};
  rect.intensity = 40.0f;  // nits: x 0.5 m^2 = 20 cd
  rect.width = 1.0f;
  rect.height = 0.5f;
  SceneLight disk = rect;
  disk.type = SceneLight::Type::kDisk;
  disk.position = {-1.0f, 2.5f, -1.0f};
  disk.direction = {0.0f, -1.0f, 0.0f};
  disk.tangent = {1.0f, 0.0f, 0.0f};
  disk.bitangent = {0.0f, 0.0f, -1.0f};
  disk.color = {0.7f, 0.8f, 1.0f};
  disk.width = disk.height = 0.6f;
  scene.lights[1] = rect;
  scene.lights[2] = disk;
  return scene;
}

View room_view() {
  View view;
  view.pose = test::look_at({0.2, 1.5, 1.5}, {0.0, 0.8, -4.0});
  view.fov = test::fov_from_tangents(0.7, 0.55);
  return view;
}

struct ShadingRig {
  ShadingRig(vk::Context& ctx, const Scene& scene, const LightSlots* slots = nullptr)
      : gpu_scene(ctx, scene),
        gbuffer_pass(ctx, gpu_scene),
        warp_pass(ctx),
        shading_pass(ctx, 1, slots),
        gbuffer(GBuffer::create(ctx, kExtent)),
        warp(WarpTargets::create(ctx, kExtent, WarpOutputs{true, false})),
        output(create_shading_output(ctx, kExtent)) {}

  void run(vk::Context& ctx, const View& view, const VisibilityInput& vis, const ShadingSettings& settings) {
    const Camera camera = display_camera(view, kExtent);
    ctx.submit_and_wait([&](VkCommandBuffer cmd) {
      gbuffer_pass.record(cmd, gbuffer, camera, kNear);
      WarpFrame frame;
      frame.depth = &gbuffer.depth;
      frame.display = camera;
      frame.near_plane = kNear;
      frame.sources[0].visibility = &vis;
      warp_pass.record(cmd, 0, frame, warp);
      shading_pass.record(cmd, 0, gbuffer, warp, camera, kNear, gpu_scene.lights(), settings, output);
    });
  }

  ClientScene gpu_scene;
  GBufferPass gbuffer_pass;
  WarpPass warp_pass;
  ShadingPass shading_pass;
  GBuffer gbuffer;
  WarpTargets warp;
  vk::Image output;
};

uint8_t to_byte(float v) { return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

// The shading pass's output against the shading equation evaluated on the CPU (light_eval.h, the same header).
// With `slots`, field f is the light slot f holds at the pixel's world point (LightSlots::light_at, in double).
void expect_cpu_shading(vk::Context& context, const Scene& scene, const LightSlots* slots = nullptr) {
  const View view = room_view();
  const Camera camera = display_camera(view, kExtent);
  const Camera traced = Camera::with_guard_band(view, kExtent, kGuard);
  // The mask's fields follow the lights (light_layout.hpp) or their slots: a soft field's three bits hold its
  // Gray-coded level; random bits over every field give every level.
  bool slot_soft[kMaxLights] = {};
  if (slots)
    for (uint32_t f = 0; f < slots->slot_count(); ++f) slot_soft[f] = slots->soft_slots()[f];
  const VisibilityLayout layout =
      slots ? VisibilityLayout::for_lights(std::span<const bool>(slot_soft, slots->slot_count()))
            : layout_for_lights(scene.lights);
  const VisibilityBuffer vis =
      make_random_visibility(traced.extent.width, traced.extent.height, layout.total_bits(), 42);
  ShadingRig rig(context, scene, slots);
  ShadingSettings settings;
  settings.exposure = 1.3f;
  rig.run(context, view, VisibilityInput{&vis, traced, {}, 0}, settings);

  const std::vector<float> depth = test::read_pixels<float>(context, rig.gbuffer.depth);
  const std::vector<float> normal = test::read_normals(context, rig.gbuffer.normal);
  const std::vector<uint8_t> albedo = test::read_pixels<uint8_t>(context, rig.gbuffer.albedo, 4);
  const std::vector<uint32_t> mask = test::read_pixels<uint32_t>(context, rig.warp.mask);
  const std::vector<uint8_t> out = test::read_pixels<uint8_t>(context, rig.output, 4);
  const std::vector<PackedLight> lights = pack_lights(scene.lights, camera.T_world_eye.position);

  size_t surface = 0, lit = 0, worst = 0, slot_lights_shaded = 0;
  std::array<size_t, kDefaultSoftLevels> soft_levels{};
  for (uint32_t j = 0; j < kExtent.height; ++j) {
    for (uint32_t i = 0; i < kExtent.width; ++i) {
      const size_t p = size_t{j} * kExtent.width + i;
      glm::vec3 expected;
      if (depth[p] == 0.0f) {
        expected = glm::vec3(display_encode::srgb_encode(settings.background.r),
                             display_encode::srgb_encode(settings.background.g),
                             display_encode::srgb_encode(settings.background.b));
      } else {
        ++surface;
        const glm::vec3 pos(eye_to_world_rotation(camera) * eye_point_from_depth(camera, kNear, i + 0.5, j + 0.5,
                                                                                  depth[p]));
        const glm::vec3 n = glm::normalize(glm::vec3(normal[p * 4], normal[p * 4 + 1], normal[p * 4 + 2]));
        glm::vec3 sum(0.0f);
        const glm::dvec3 world = glm::dvec3(pos) + camera.T_world_eye.position;
        for (uint32_t f = 0; f < layout.light_count; ++f) {
          const float k = layout.visibility(mask[p], f);  // the bit, or level / 7
          if (k == 0.0f) continue;
          const uint32_t l = slots ? slots->light_at(f, world) : f;
          if (l == kNoSlotLight) continue;
          if (slots) ++slot_lights_shaded;
          if (layout.is_soft(f)) {
            ++soft_levels[gray_decode(layout.field(mask[p], f))];
            sum += k * light_contribution(lights[l], sample_light(lights[l], pos, n), n);
          } else {
            sum += light_contribution(lights[l], sample_light(lights[l], pos, n), n);
          }
        }
        const glm::vec3 a(albedo[p * 4] / 255.0f, albedo[p * 4 + 1] / 255.0f, albedo[p * 4 + 2] / 255.0f);
        const glm::vec3 radiance = a * 0.31830988618f * sum;
        if (radiance.r + radiance.g + radiance.b > 0.01f) ++lit;
        expected = display_encode::encode_radiance(radiance, settings.exposure);
      }
      for (int c = 0; c < 3; ++c) {
        const int diff = std::abs(static_cast<int>(out[p * 4 + c]) - static_cast<int>(to_byte(expected[c])));
        worst = std::max(worst, static_cast<size_t>(diff));
        ASSERT_LE(diff, 1) << "pixel " << i << "," << j << " channel " << c;
      }
      ASSERT_EQ(out[p * 4 + 3], 255);
    }
  }
  EXPECT_GT(surface, kExtent.width * kExtent.height / 2);
  EXPECT_GT(lit, surface / 4) << "the test scene should be mostly lit";
  EXPECT_LE(worst, 1u);
  if (slots) {
    EXPECT_GT(slot_lights_shaded, surface) << "the test should shade more than one slot's light per pixel";
  }
  if (layout.any_soft()) {
    for (uint32_t level = 1; level < kDefaultSoftLevels; ++level) EXPECT_GT(soft_levels[level], 0u) << level;
  }
}

TEST_F(ClientShadingTest, MatchesTheCpuShadingEquation) { expect_cpu_shading(ctx(), lit_room()); }

// lit_room's geometry with 60 point lights of 1.5 m range over it (light slots: about 15 fields).
Scene many_lit_room() {
  Scene scene = lit_room();
  scene.lights.clear();
  for (int i = 0; i < 60; ++i) {
    SceneLight l;
    l.type = SceneLight::Type::kPoint;
    l.position = {-3.5f + 7.0f * static_cast<float>(i % 6) / 5.0f, 0.6f + 0.5f * static_cast<float>(i % 4),
                  0.5f - 6.0f * static_cast<float>(i / 6) / 9.0f};
    l.color = {1.0f, 0.8f + 0.02f * static_cast<float>(i % 10), 0.7f};
    l.intensity = 3.0f;
    l.range = 1.5f;
    scene.lights.push_back(l);
  }
  return scene;
}

// More than 32 lights: each pixel's fields shade the lights its cell holds, as on the CPU.
TEST_F(ClientShadingTest, LightSlotsMatchTheCpuShadingEquation) {
  const Scene scene = many_lit_room();
  const LightSlots slots = LightSlots::assign(scene.lights);
  ASSERT_FALSE(slots.is_identity());
  ASSERT_TRUE(slots.dropped().empty()) << slots.describe();
  expect_cpu_shading(ctx(), scene, &slots);
}

// The eye pipeline with light slots: the deferred path (the forward pass shades by light index), the warp given one
// light per field, and the same pixels as the passes above; at most 32 lights stay the identity.
TEST_F(ClientShadingTest, EyePipelineShadesLightSlotsOnTheDeferredPath) {
  const Scene scene = many_lit_room();
  const View view = room_view();
  const Camera traced = Camera::with_guard_band(view, kExtent, kGuard);
  ClientScene gpu_scene(ctx(), scene);
  ASSERT_FALSE(gpu_scene.light_slots().is_identity());
  ASSERT_EQ(gpu_scene.field_lights().size(), gpu_scene.light_slots().slot_count());
  bool soft[kMaxLights] = {};
  const VisibilityLayout layout =
      VisibilityLayout::for_lights(std::span<const bool>(soft, gpu_scene.light_slots().slot_count()));
  const VisibilityBuffer vis = make_random_visibility(traced.extent.width, traced.extent.height, layout.total_bits(), 7);
  const VisibilityInput input{&vis, traced, {}, 0};

  EyePipeline eye(ctx(), gpu_scene, kExtent);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { eye.record(cmd, 0, view, input); });
  EXPECT_FALSE(eye.read_stats(0).forward);
  const std::vector<uint8_t> got = test::read_pixels<uint8_t>(ctx(), eye.output(), 4);

  ShadingRig rig(ctx(), scene, &gpu_scene.light_slots());
  rig.run(ctx(), view, input, ShadingSettings{});
  EXPECT_EQ(got, test::read_pixels<uint8_t>(ctx(), rig.output, 4));

  Scene few = lit_room();
  ClientScene few_scene(ctx(), few);
  EXPECT_TRUE(few_scene.light_slots().is_identity());
  EXPECT_EQ(few_scene.field_lights().size(), few.lights.size());
}

// The forward pass without shadows (Lambert) over many lights shades each field's light where the fragment is:
// the shading pass's pixels for an all-lit mask, within 1/255. Its warp modes refuse light slots.
TEST_F(ClientShadingTest, ForwardLambertShadesLightSlotsAsTheShadingPass) {
  const Scene scene = many_lit_room();
  const View view = room_view();
  const Camera camera = display_camera(view, kExtent);
  const Camera traced = Camera::with_guard_band(view, kExtent, kGuard);
  ClientScene gpu_scene(ctx(), scene);
  ForwardOptions options;
  options.mode = ForwardMode::kLambert;
  ForwardPass pass(ctx(), gpu_scene, options);
  ForwardTargets targets = ForwardTargets::create(ctx(), kExtent, options);
  ForwardFrame frame;
  frame.display = camera;
  frame.near_plane = kNear;
  frame.lights = gpu_scene.lights();
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { pass.record(cmd, 0, frame, targets); });
  const std::vector<uint8_t> forward = test::read_pixels<uint8_t>(ctx(), targets.colour, 4);

  VisibilityBuffer lit = VisibilityBuffer::create(traced.extent.width, traced.extent.height,
                                                  gpu_scene.light_slots().slot_count());
  for (size_t p = 0; p < lit.pixel_count(); ++p) lit.set_mask_at(p, lit.light_bits());
  ShadingRig rig(ctx(), scene, &gpu_scene.light_slots());
  rig.run(ctx(), view, VisibilityInput{&lit, traced, {}, 0}, ShadingSettings{});
  const std::vector<uint8_t> deferred = test::read_pixels<uint8_t>(ctx(), rig.output, 4);
  ASSERT_EQ(forward.size(), deferred.size());
  size_t lit_pixels = 0;
  for (size_t i = 0; i < forward.size(); ++i) {
    ASSERT_LE(std::abs(int(forward[i]) - int(deferred[i])), 1) << "byte " << i;
    lit_pixels += i % 4 == 0 && forward[i] > 40;
  }
  EXPECT_GT(lit_pixels, forward.size() / 4 / 4);

  ForwardOptions paper = options;
  paper.mode = ForwardMode::kPaperWarp;
  ForwardPass warp_pass(ctx(), gpu_scene, paper);
  ForwardTargets warp_targets = ForwardTargets::create(ctx(), kExtent, paper);
  EXPECT_THROW(ctx().submit_and_wait([&](VkCommandBuffer cmd) { warp_pass.record(cmd, 0, frame, warp_targets); }),
               std::invalid_argument);
}

// Rect and disk lights: one-sided, cosine-weighted, identically on the GPU and the CPU. Both have an extent, so
// each has a soft field (three Gray-coded bits) and shades with k = level / 7.
TEST_F(ClientShadingTest, AreaLightsMatchTheCpuShadingEquation) {
  const Scene scene = area_lit_room();
  for (const SceneLight& l : scene.lights) ASSERT_FALSE(validate_light(l).has_value()) << l.name;
  const VisibilityLayout layout = layout_for_lights(scene.lights);
  ASSERT_FALSE(layout.is_soft(0));
  ASSERT_TRUE(layout.is_soft(1) && layout.is_soft(2));
  EXPECT_EQ(soft_light_mask(layout), 6u);
  expect_cpu_shading(ctx(), scene);
}

// A sphere light (a point light with a radius) takes a soft field too; the punctual lights around it keep theirs.
TEST_F(ClientShadingTest, SphereLightShadesWithItsLevel) {
  Scene scene = lit_room();
  scene.lights[0].radius = 0.2f;
  ASSERT_EQ(soft_light_mask(layout_for_lights(scene.lights)), 1u);
  expect_cpu_shading(ctx(), scene);
}

TEST_F(ClientShadingTest, ShadowedPixelsGetNoLight) {
  const Scene scene = lit_room();
  const View view = room_view();
  const Camera traced = Camera::with_guard_band(view, kExtent, kGuard);
  const VisibilityBuffer dark = make_uniform_visibility(traced.extent.width, traced.extent.height, 3, 0);
  ShadingRig rig(ctx(), scene);
  rig.run(ctx(), view, VisibilityInput{&dark, traced, {}, 0}, ShadingSettings{});
  const std::vector<float> depth = test::read_pixels<float>(ctx(), rig.gbuffer.depth);
  const std::vector<uint8_t> out = test::read_pixels<uint8_t>(ctx(), rig.output, 4);
  for (size_t p = 0; p < depth.size(); ++p) {
    if (depth[p] == 0.0f) continue;
    ASSERT_EQ(out[p * 4] + out[p * 4 + 1] + out[p * 4 + 2], 0) << p;
  }
}

TEST_F(ClientShadingTest, DebugViews) {
  const Scene scene = lit_room();
  const View view = room_view();
  const Camera traced = Camera::with_guard_band(view, kExtent, kGuard);
  const VisibilityBuffer vis = make_stripe_visibility(traced.extent.width, traced.extent.height, 3, 8);
  ShadingRig rig(ctx(), scene);
  const std::vector<float> depth = [&] {
    rig.run(ctx(), view, VisibilityInput{}, ShadingSettings{});
    return test::read_pixels<float>(ctx(), rig.gbuffer.depth);
  }();

  // Per-light visibility: white where the light's bit is set, black where not.
  ShadingSettings settings;
  settings.view = ShadingView::kLightVisibility;
  settings.debug_light = 1;
  rig.run(ctx(), view, VisibilityInput{&vis, traced, {}, 0}, settings);
  std::vector<uint32_t> mask = test::read_pixels<uint32_t>(ctx(), rig.warp.mask);
  std::vector<uint8_t> out = test::read_pixels<uint8_t>(ctx(), rig.output, 4);
  for (size_t p = 0; p < depth.size(); ++p) {
    if (depth[p] == 0.0f) continue;
    const bool bit = ((mask[p] >> 1) & 1u) != 0;
    // 0.9 and 0.1 of 255 are 229.5 and 25.5: either neighbour is a correct rounding (lavapipe rounds up, an
    // NVIDIA H100 gave 229).
    ASSERT_NEAR(out[p * 4], bit ? 230 : 26, 1) << p;
    ASSERT_EQ(out[p * 4 + 1], out[p * 4]);
  }

  // Unknown pixels (no visibility yet): tinted magenta.
  settings.view = ShadingView::kUnknown;
  rig.run(ctx(), view, VisibilityInput{}, settings);
  out = test::read_pixels<uint8_t>(ctx(), rig.output, 4);
  for (size_t p = 0; p < depth.size(); ++p) {
    if (depth[p] == 0.0f) continue;
    ASSERT_GE(out[p * 4], 153) << p;
    ASSERT_GE(out[p * 4 + 2], 153) << p;
    ASSERT_LT(out[p * 4 + 1], 103) << p;
  }

  // Red and blue swapped for BGRA swapchains: the same bytes in the other order.
  settings.view = ShadingView::kShaded;
  rig.run(ctx(), view, VisibilityInput{&vis, traced, {}, 0}, settings);
  const std::vector<uint8_t> rgba = test::read_pixels<uint8_t>(ctx(), rig.output, 4);
  settings.swap_red_blue = true;
  rig.run(ctx(), view, VisibilityInput{&vis, traced, {}, 0}, settings);
  const std::vector<uint8_t> bgra = test::read_pixels<uint8_t>(ctx(), rig.output, 4);
  for (size_t p = 0; p < depth.size(); ++p) {
    ASSERT_EQ(bgra[p * 4], rgba[p * 4 + 2]);
    ASSERT_EQ(bgra[p * 4 + 1], rgba[p * 4 + 1]);
    ASSERT_EQ(bgra[p * 4 + 2], rgba[p * 4]);
  }
  settings.swap_red_blue = false;

  // Albedo: the sRGB encoding of the G-buffer's linear albedo.
  settings.view = ShadingView::kAlbedo;
  rig.run(ctx(), view, VisibilityInput{}, settings);
  out = test::read_pixels<uint8_t>(ctx(), rig.output, 4);
  const std::vector<uint8_t> albedo = test::read_pixels<uint8_t>(ctx(), rig.gbuffer.albedo, 4);
  for (size_t p = 0; p < depth.size(); ++p) {
    if (depth[p] == 0.0f) continue;
    const float expected = display_encode::srgb_encode(albedo[p * 4] / 255.0f);
    ASSERT_LE(std::abs(static_cast<int>(out[p * 4]) - static_cast<int>(to_byte(expected))), 1) << p;
  }
}

TEST_F(ClientShadingTest, MismatchedSizesAreRejected) {
  const Scene scene = lit_room();
  ShadingRig rig(ctx(), scene);
  vk::Image small = create_shading_output(ctx(), Extent{32, 32});
  const Camera camera = display_camera(room_view(), kExtent);
  EXPECT_THROW(ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    rig.shading_pass.record(cmd, 0, rig.gbuffer, rig.warp, camera, kNear, rig.gpu_scene.lights(),
                            ShadingSettings{}, small);
  }),
               std::invalid_argument);
  EXPECT_THROW(ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    rig.shading_pass.record(cmd, 1, rig.gbuffer, rig.warp, camera, kNear, rig.gpu_scene.lights(),
                            ShadingSettings{}, rig.output);
  }),
               std::invalid_argument);
}

// Debug views read optional warp outputs: without them the pass refuses instead of reading placeholders.
TEST_F(ClientShadingTest, DebugViewsNeedTheirWarpOutputs) {
  const Scene scene = lit_room();
  ShadingRig rig(ctx(), scene);  // status on, motion vectors off
  const Camera camera = display_camera(room_view(), kExtent);
  WarpTargets bare = WarpTargets::create(ctx(), kExtent, WarpOutputs{});
  EXPECT_FALSE(bare.has_status());
  EXPECT_FALSE(bare.has_motion());
  for (const ShadingView view : {ShadingView::kLightVisibility, ShadingView::kUnknown, ShadingView::kMotion}) {
    SCOPED_TRACE(static_cast<int>(view));
    EXPECT_FALSE(debug_outputs_available(view, bare));
    ShadingSettings settings;
    settings.view = view;
    EXPECT_THROW(ctx().submit_and_wait([&](VkCommandBuffer cmd) {
      rig.shading_pass.record(cmd, 0, rig.gbuffer, bare, camera, kNear, rig.gpu_scene.lights(), settings, rig.output);
    }),
                 std::invalid_argument);
  }
  EXPECT_TRUE(debug_outputs_available(ShadingView::kUnknown, rig.warp));
  EXPECT_FALSE(debug_outputs_available(ShadingView::kMotion, rig.warp));
  for (const ShadingView view : {ShadingView::kShaded, ShadingView::kAlbedo, ShadingView::kNormal}) {
    EXPECT_TRUE(debug_outputs_available(view, bare));
  }
}

}  // namespace
}  // namespace dhr::render
