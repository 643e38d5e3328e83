// The full warp on the real passes (G-buffer, traced-camera depth, shadow maps, both eyes): the GPU equals
// the CPU reference (warp_reference with shadow_mask_reference) on every pixel whose decisions are not within
// float rounding of flipping; the client's shadow maps agree with Embree on the default room away from shadow
// edges; and a synthetic disocclusion (an occluder in front of its own shadow, the camera sliding sideways)
// where the paper's warp takes the occluder's mask and the full warp, the shipped default (edges) and edges with
// the depth test at a half-resolution traced depth do not.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "client_test_helpers.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "metrics/visibility_synthetic.hpp"
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/light_layout.hpp"
#include "render/render_camera.hpp"
#include "render/shadow_maps.hpp"
#include "render/warp_reference.hpp"
#include "plan/shipped_defaults.hpp"
#include "scene/scene.hpp"
#include "test_scenes.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

namespace fs = std::filesystem;
using ClientWarpFullTest = vk::test::VulkanTest;

constexpr Extent kExtent{96, 72};
constexpr GuardBand kGuard{4, 3};
constexpr double kMargin = 2e-3;  // warp_reference.hpp

Scene load_room(const char* relative) {
  const SceneLoadResult loaded = load_scene((fs::path(DHR_SOURCE_DIR) / relative).string());
  if (!loaded) throw std::runtime_error(loaded.error);
  return *loaded.scene;
}

Scene default_room() { return load_room(kDefaultScenePath); }

// The default room, and its sibling whose lights have an extent (a rect panel: one-sided, its cube map and its
// shadow rays at its centre; a sphere light: as a point light).
class ClientWarpFullRooms : public ClientWarpFullTest, public testing::WithParamInterface<const char*> {};
constexpr const char* kAreaRoomPath = "assets/scenes/default_room_area.gltf";

View room_view(double dx) {
  View view;
  view.pose = test::look_at({dx, 1.6, 1.35}, {dx - 0.1, 0.5, -0.9});
  view.fov = Fov{-0.742f, 0.742f, 0.779f, -0.779f};
  return view;
}

std::vector<glm::vec3> normals_of(const vk::Context& ctx, vk::Image& image) {
  const std::vector<float> raw = test::read_normals(ctx, image);
  std::vector<glm::vec3> out(raw.size() / 4);
  for (size_t i = 0; i < out.size(); ++i) out[i] = glm::vec3(raw[i * 4], raw[i * 4 + 1], raw[i * 4 + 2]);
  return out;
}

// Both eyes of a client, with shadow maps, rendered in one submission like the frame loop does.
class StereoRig {
 public:
  StereoRig(vk::Context& ctx, const Scene& scene, const WarpSettings& settings, uint32_t shadow_size = 256)
      : ctx_(ctx), scene_(ctx, scene), lights_(scene.lights) {
    ShadowMapSettings sm;
    sm.size = shadow_size;
    maps_ = std::make_unique<ShadowMaps>(ctx, scene_, sm);
    EyePipelineOptions options;
    options.frames_in_flight = 1;
    options.warp_status = true;
    options.warp = settings;
    for (auto& eye : eyes_) eye = std::make_unique<EyePipeline>(ctx, scene_, kExtent, options);
  }

  void run(const std::array<View, 2>& views, const std::array<VisibilityInput, 2>& inputs,
           const std::array<VisibilityInput, 2>& older = {}) {
    ctx_.submit_and_wait([&](VkCommandBuffer cmd) {
      for (size_t e = 0; e < 2; ++e) eyes_[e]->prepare(cmd, 0, inputs[e], &older[e]);
      for (size_t e = 0; e < 2; ++e) {
        WarpSourceInput other;
        other.visibility = &inputs[1 - e];
        if (inputs[1 - e].buffer != nullptr) other.traced_depth = eyes_[1 - e]->traced_depth(inputs[1 - e].traced);
        eyes_[e]->record(cmd, 0, views[e], inputs[e], other, maps_.get(), &older[e]);
      }
    });
  }

  EyePipeline& eye(size_t e) { return *eyes_[e]; }
  ShadowMaps& maps() { return *maps_; }
  const std::vector<SceneLight>& lights() const { return lights_; }

  ShadowReference shadow_reference(std::vector<float>& atlas_storage) {
    vk::Image& atlas = maps_->atlas();
    atlas_storage.resize(size_t{atlas.width()} * atlas.height());
    vk::read_image(ctx_, atlas, atlas_storage.data(), atlas_storage.size() * sizeof(float));
    ShadowReference ref;
    ref.atlas = atlas_storage;
    ref.face_size = maps_->face_size();
    ref.tiles = maps_->tiles();
    ref.settings = maps_->settings();
    return ref;
  }

 private:
  vk::Context& ctx_;
  ClientScene scene_;
  std::vector<SceneLight> lights_;
  std::unique_ptr<ShadowMaps> maps_;
  std::array<std::unique_ptr<EyePipeline>, 2> eyes_;
};

TEST_P(ClientWarpFullRooms, GpuMatchesCpuReferenceWithEveryIngredient) {
  const Scene scene = load_room(GetParam());
  StereoRig rig(ctx(), scene, WarpSettings::full());
  const std::array<View, 2> views = {room_view(-0.032), room_view(0.032)};
  struct Move {
    const char* name;
    glm::dvec3 translation;
    double yaw_deg;
    bool drop_rows;  // source 0 (the left eye) lost every third row
    double older_yaw_deg;  // the previous buffers (source 2): traced from the display pose turned this much
    bool older;
  };
  for (const Move& move : {Move{"small", {0.03, -0.01, 0.02}, 2.0, false, 0.0, false},
                           Move{"turn_and_lost_rows", {-0.08, 0.02, 0.05}, 14.0, true, -8.0, true}}) {
    SCOPED_TRACE(move.name);
    std::array<Camera, 2> traced;
    std::array<Camera, 2> older_traced;
    std::array<VisibilityBuffer, 2> vis;
    std::array<VisibilityBuffer, 2> older_vis;
    std::array<VisibilityInput, 2> inputs;
    std::array<VisibilityInput, 2> older;
    std::vector<uint8_t> rows;
    for (size_t e = 0; e < 2; ++e) {
      View old = views[e];
      old.pose.position += move.translation;
      old.pose = test::rotated(old.pose, move.yaw_deg, 0.0);
      traced[e] = Camera::with_guard_band(old, kExtent, kGuard);
      vis[e] = make_random_visibility(traced[e].extent.width, traced[e].extent.height,
                                      static_cast<uint32_t>(scene.lights.size()), 11 + e);
      inputs[e].buffer = &vis[e];
      inputs[e].traced = traced[e];
      if (move.older) {
        View previous = views[e];
        previous.pose = test::rotated(previous.pose, move.older_yaw_deg, 0.0);
        older_traced[e] = Camera::with_guard_band(previous, kExtent, kGuard);
        older_vis[e] = make_random_visibility(older_traced[e].extent.width, older_traced[e].extent.height,
                                              static_cast<uint32_t>(scene.lights.size()), 21 + e);
        older[e].buffer = &older_vis[e];
        older[e].traced = older_traced[e];
      }
    }
    if (move.drop_rows) {
      rows.assign(traced[0].extent.height, 1);
      for (size_t r = 0; r < rows.size(); r += 3) rows[r] = 0;
      inputs[0].row_valid = rows;
    }
    rig.run(views, inputs, older);

    std::vector<float> atlas;
    const ShadowReference shadow = rig.shadow_reference(atlas);
    std::array<std::vector<float>, 2> traced_depth;
    std::array<std::vector<float>, 2> older_depth;
    for (size_t e = 0; e < 2; ++e) {
      vk::Image* image = rig.eye(e).traced_depth(traced[e]);
      ASSERT_NE(image, nullptr);
      traced_depth[e] = test::read_pixels<float>(ctx(), *image);
      if (move.older) {
        vk::Image* previous = rig.eye(e).traced_depth(older_traced[e]);
        ASSERT_NE(previous, nullptr);  // both traced depths are held
        older_depth[e] = test::read_pixels<float>(ctx(), *previous);
      }
    }
    for (size_t e = 0; e < 2; ++e) {
      SCOPED_TRACE("eye " + std::to_string(e));
      EyePipeline& eye = rig.eye(e);
      const std::vector<float> depth = test::read_pixels<float>(ctx(), eye.gbuffer().depth);
      const std::vector<glm::vec3> normals = normals_of(ctx(), eye.gbuffer().normal);
      const std::vector<uint32_t> masks = test::read_pixels<uint32_t>(ctx(), eye.warp().mask);
      const std::vector<uint32_t> status = test::read_pixels<uint32_t>(ctx(), eye.warp().status);
      WarpInput in;
      in.depth = depth;
      in.normals = normals;
      in.display = display_camera(views[e], kExtent);
      in.sources[0] = WarpSource{&vis[e], traced[e], e == 0 ? inputs[0].row_valid : std::span<const uint8_t>{},
                                 traced_depth[e]};
      in.sources[1] = WarpSource{&vis[1 - e], traced[1 - e], e == 1 ? inputs[0].row_valid : std::span<const uint8_t>{},
                                 traced_depth[1 - e]};
      if (move.older) in.sources[2] = WarpSource{&older_vis[e], older_traced[e], {}, older_depth[e]};
      in.settings = WarpSettings::full();
      in.shadow = &shadow;
      in.lights = rig.lights();
      const WarpResult cpu = warp_reference(in);
      size_t judged = 0, mismatched = 0;
      for (size_t i = 0; i < depth.size(); ++i) {
        if (cpu.margin[i] < kMargin) continue;
        ++judged;
        const bool same = masks[i] == cpu.masks[i] && (status[i] & 0xFFu) == static_cast<uint32_t>(cpu.status[i]) &&
                          (status[i] >> 8) == static_cast<uint32_t>(cpu.fill[i]);
        if (!same && ++mismatched <= 5) {
          ADD_FAILURE() << "pixel " << i % kExtent.width << "," << i / kExtent.width << ": gpu mask " << masks[i]
                        << " status " << (status[i] & 0xFFu) << " fill " << (status[i] >> 8) << ", cpu mask "
                        << cpu.masks[i] << " status " << to_string(cpu.status[i]) << " fill "
                        << static_cast<int>(cpu.fill[i]) << " margin " << cpu.margin[i];
        }
      }
      EXPECT_EQ(mismatched, 0u);
      // Shadow lookups add texel and face boundaries to the flips that are excluded (~5 % of the pixels).
      EXPECT_GT(judged, depth.size() * 90 / 100) << "too many decisions near a flip for a meaningful test";
      const WarpCounts counts = eye.read_stats(0).warp;
      // Random masks: neighbours disagree everywhere. Soft fields blend their levels instead of asking the maps,
      // and the area room's one hard light is mostly decided by the maps first (shadow_first).
      if (!layout_for_lights(scene.lights).any_soft()) {
        EXPECT_GT(counts.edges_shadow_map, 0u);
      }
      if (move.drop_rows && e == 0) {
        EXPECT_GT(counts.filled_other_eye, 0u);
        EXPECT_GT(counts[WarpStatus::kMissingRow] + counts[WarpStatus::kOutside], 0u);
      }
      if (move.yaw_deg > 10.0) {
        EXPECT_GT(counts.filled_shadow_map, 0u);  // outside every buffer
      }
      if (move.older) {
        EXPECT_GT(counts.filled_older, 0u);  // outside both eyes' newest buffers, inside the previous one
        EXPECT_GT(cpu.counts.filled_older, 0u);
      }
      if (move.drop_rows && e == 0) {
        EXPECT_GT(cpu.counts.filled_neighbour, 0u);  // rows lost in every buffer
      }
      // The GPU's counts are the CPU's up to the pixels too close to a flip to judge.
      const uint64_t slack = depth.size() - judged;
      EXPECT_LE(std::abs(static_cast<int64_t>(counts.filled_other_eye) -
                         static_cast<int64_t>(cpu.counts.filled_other_eye)),
                static_cast<int64_t>(slack));
      EXPECT_LE(std::abs(static_cast<int64_t>(counts.filled_older) - static_cast<int64_t>(cpu.counts.filled_older)),
                static_cast<int64_t>(slack));
      EXPECT_LE(std::abs(static_cast<int64_t>(counts.filled_neighbour) -
                         static_cast<int64_t>(cpu.counts.filled_neighbour)),
                static_cast<int64_t>(slack));
    }
  }
}

// The truth of a camera from Embree (the server's tracer), display-sized (no guard band).
VisibilityBuffer embree_truth(const Scene& scene, const Camera& camera) {
  server::TracerOptions options;
  options.threads = 1;
  server::EmbreeTracer tracer(scene, options);
  VisibilityBuffer out;
  server::TraceStats stats;
  tracer.trace(camera, out, stats);
  return out;
}

TEST_P(ClientWarpFullRooms, ShadowMapsAgreeWithEmbreeAwayFromShadowEdges) {
  const Scene scene = load_room(GetParam());
  WarpSettings local;
  local.shadow_fill = true;  // no server: every surface pixel from the shadow maps
  StereoRig rig(ctx(), scene, local, 1024);
  const std::array<View, 2> views = {room_view(-0.032), room_view(0.032)};
  rig.run(views, {VisibilityInput{}, VisibilityInput{}});
  const Camera camera = display_camera(views[0], kExtent);
  const VisibilityBuffer truth = embree_truth(scene, camera);
  const std::vector<uint32_t> masks = test::read_pixels<uint32_t>(ctx(), rig.eye(0).warp().mask);
  const std::vector<float> depth = test::read_pixels<float>(ctx(), rig.eye(0).gbuffer().depth);
  // The client's masks are in the scene's layout (a soft light's field holds PCSS's level); each side's light i
  // is compared as lit or not (visibility >= 0.5: a soft light's penumbra midpoint is about where the hard
  // shadow of its centre falls). The truth's layout is the hard one when it has one bit per light.
  const VisibilityLayout layout = layout_for_lights(scene.lights);
  const VisibilityLayout truth_layout =
      truth.light_count == scene.lights.size() ? VisibilityLayout::hard(truth.light_count) : layout;
  const auto lit_bits = [](const VisibilityLayout& l, uint32_t mask) {
    uint32_t out = 0;
    for (uint32_t k = 0; k < l.light_count; ++k) out |= l.visibility(mask, k) >= 0.5f ? 1u << k : 0u;
    return out;
  };
  uint64_t interior = 0, interior_agree = 0, surface = 0, surface_agree = 0;
  for (uint32_t y = 0; y < kExtent.height; ++y) {
    for (uint32_t x = 0; x < kExtent.width; ++x) {
      const size_t i = size_t{y} * kExtent.width + x;
      if (!(depth[i] > 0.0f)) continue;
      const uint32_t want = truth.get(x, y);
      const bool agree = lit_bits(layout, masks[i]) == lit_bits(truth_layout, want);
      ++surface;
      surface_agree += agree;
      // Away from edges: the truth is the same in the 3x3 neighbourhood (inside the image).
      bool uniform = x > 0 && y > 0 && x + 1 < kExtent.width && y + 1 < kExtent.height;
      for (int dy = -1; uniform && dy <= 1; ++dy) {
        for (int dx = -1; uniform && dx <= 1; ++dx) uniform = truth.get(x + dx, y + dy) == want;
      }
      if (!uniform) continue;
      ++interior;
      interior_agree += agree;
    }
  }
  const double interior_share = double(interior_agree) / double(interior);
  const double surface_share = double(surface_agree) / double(surface);
  std::printf("shadow maps vs Embree, %s: %.4f of %llu pixels away from shadow edges agree, %.4f of all "
              "%llu surface pixels\n",
              GetParam(), interior_share, static_cast<unsigned long long>(interior), surface_share,
              static_cast<unsigned long long>(surface));
  EXPECT_GT(interior, surface / 2);
  EXPECT_GE(interior_share, 0.995);
  EXPECT_GE(surface_share, 0.97);
}

INSTANTIATE_TEST_SUITE_P(Rooms, ClientWarpFullRooms, testing::Values(kDefaultScenePath, kAreaRoomPath),
                         [](const testing::TestParamInfo<const char*>& param) {
                           return std::string(param.param) == kAreaRoomPath ? "area_lights" : "default";
                         });

TEST_F(ClientWarpFullTest, DisocclusionLeaksTheOccludersMaskInThePaperWarpOnly) {
  // A floor, a floating slab facing a point light in front of it, and the slab's shadow on the floor behind.
  Scene scene = dhr::test::make_empty_scene();
  dhr::test::add_grid(scene, {-3.0f, 0.0f, 3.0f}, {6.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -6.0f}, 8, dhr::test::kSingleSided);
  dhr::test::add_box(scene, {-0.35f, 0.3f, -0.05f}, {0.35f, 1.0f, 0.05f}, dhr::test::kSingleSided);
  scene.lights.push_back(dhr::test::point_light({0.0f, 2.2f, 2.0f}, 20.0f));
  dhr::test::finalize(scene);
  // The traced (old) camera sees the slab in front of the shadowed floor; the display slid 0.5 m sideways
  // and sees floor that was behind the slab.
  View old_view;
  old_view.pose = test::look_at({-0.5, 1.0, 2.6}, {0.0, 0.4, -0.6});
  old_view.fov = Fov{-0.7f, 0.7f, 0.55f, -0.55f};
  View now = old_view;
  now.pose = test::look_at({0.0, 1.0, 2.6}, {0.0, 0.4, -0.6});
  const Camera traced = Camera::with_guard_band(old_view, kExtent, kGuard);
  const VisibilityBuffer old_truth = embree_truth(scene, traced);
  const VisibilityBuffer truth = embree_truth(scene, display_camera(now, kExtent));
  VisibilityInput input;
  input.buffer = &old_truth;
  input.traced = traced;

  auto wrong_pixels = [&](const WarpSettings& settings, WarpCounts* counts) {
    StereoRig rig(ctx(), scene, settings, 512);
    rig.run({now, now}, {input, VisibilityInput{}});
    const std::vector<uint32_t> masks = test::read_pixels<uint32_t>(ctx(), rig.eye(0).warp().mask);
    const std::vector<float> depth = test::read_pixels<float>(ctx(), rig.eye(0).gbuffer().depth);
    if (counts != nullptr) *counts = rig.eye(0).read_stats(0).warp;
    uint64_t wrong = 0;
    for (size_t i = 0; i < masks.size(); ++i) {
      if (depth[i] > 0.0f) wrong += (masks[i] & 1u) != truth.mask_at(i);
    }
    return wrong;
  };
  WarpCounts full_counts, shipped_counts, depth_counts;
  const uint64_t paper = wrong_pixels(WarpSettings{}, nullptr);
  const uint64_t full = wrong_pixels(WarpSettings::full(), &full_counts);
  // What ships for this scene (--warp auto: edges, its light is hard), and --warp edges-depth at the shipped depth
  // scale with the traced camera rendered (the rig's one frame has no previous frame to splat).
  const uint64_t shipped = wrong_pixels(
      warp_settings_for(client::resolve_warp(client::shipped::kWarp, scene.has_soft_lights()), client::shipped::kDepthScale),
      &shipped_counts);
  const uint64_t depth = wrong_pixels(WarpSettings::server_edges_depth(client::shipped::kDepthScale), &depth_counts);
  std::printf("disocclusion: paper %llu wrong pixels, full %llu (%llu disoccluded), shipped %llu (%llu disoccluded, "
              "%llu edges from the shadow maps), edges-depth %llu (%llu disoccluded)\n",
              static_cast<unsigned long long>(paper), static_cast<unsigned long long>(full),
              static_cast<unsigned long long>(full_counts[WarpStatus::kDisoccluded]),
              static_cast<unsigned long long>(shipped),
              static_cast<unsigned long long>(shipped_counts[WarpStatus::kDisoccluded]),
              static_cast<unsigned long long>(shipped_counts.edges_shadow_map), static_cast<unsigned long long>(depth),
              static_cast<unsigned long long>(depth_counts[WarpStatus::kDisoccluded]));
  EXPECT_GE(paper, 15u);                                   // the leak (28 pixels when written)
  EXPECT_GE(full_counts[WarpStatus::kDisoccluded], 10u);  // found by the depth test
  EXPECT_LE(full * 5, paper);
  EXPECT_LE(shipped * 5, paper);
  EXPECT_GE(depth_counts[WarpStatus::kDisoccluded], 10u);  // found by the depth test
  EXPECT_LE(depth * 5, paper);
  // The shipped edges rule has no depth test: this disocclusion is two pixels wide, so the 2x2 samples straddle
  // the slab's edge, disagree, and the shadow maps decide. Where disocclusions are wider than the samples (long
  // round trips) --warp edges-depth is the more accurate (docs/evaluation.md measures both).
}

TEST_F(ClientWarpFullTest, WithoutShadowMapsNeighboursAndThePreviousBufferFillLostRows) {
  // Default room, one eye: the newest buffer (Embree's truth for a slightly moved pose) lost two rows in three.
  // Without the shadow maps those pixels are shaded lit; the neighbour fill takes the mask of the nearest old
  // pixel on the same surface, the previous buffer (complete, traced for another pose) its own lookup.
  const Scene scene = default_room();
  const View now = room_view(-0.032);
  View moved = now;
  moved.pose.position += glm::dvec3(0.02, 0.0, 0.01);
  moved.pose = test::rotated(moved.pose, 1.5, 0.0);
  View previous = now;
  previous.pose.position += glm::dvec3(0.04, 0.0, 0.02);
  const Camera traced = Camera::with_guard_band(moved, kExtent, kGuard);
  const Camera previous_traced = Camera::with_guard_band(previous, kExtent, kGuard);
  const VisibilityBuffer newest = embree_truth(scene, traced);
  const VisibilityBuffer older = embree_truth(scene, previous_traced);
  const VisibilityBuffer truth = embree_truth(scene, display_camera(now, kExtent));
  std::vector<uint8_t> rows(traced.extent.height, 1);
  for (size_t r = 0; r < rows.size(); ++r) rows[r] = r % 3 == 0 ? 1 : 0;
  VisibilityInput input;
  input.buffer = &newest;
  input.traced = traced;
  VisibilityInput older_input;
  older_input.buffer = &older;
  older_input.traced = previous_traced;

  auto wrong_bits = [&](const WarpSettings& settings, WarpCounts& counts) {
    StereoRig rig(ctx(), scene, settings);
    rig.run({now, now}, {input, VisibilityInput{}}, {older_input, VisibilityInput{}});
    const std::vector<uint32_t> masks = test::read_pixels<uint32_t>(ctx(), rig.eye(0).warp().mask);
    const std::vector<float> depth = test::read_pixels<float>(ctx(), rig.eye(0).gbuffer().depth);
    counts = rig.eye(0).read_stats(0).warp;
    uint64_t wrong = 0;
    for (size_t i = 0; i < masks.size(); ++i) {
      if (depth[i] > 0.0f) wrong += static_cast<uint64_t>(std::popcount((masks[i] ^ truth.mask_at(i)) & truth.light_bits()));
    }
    return wrong;
  };
  WarpSettings lit = WarpSettings::full();
  lit.shadow_fill = lit.shadow_edges = lit.shadow_first = false;
  lit.older_buffer = lit.neighbour_fill = false;
  WarpSettings neighbours = lit;
  neighbours.neighbour_fill = true;
  WarpSettings older_first = neighbours;
  older_first.older_buffer = true;
  WarpCounts lit_counts, neighbour_counts, older_counts;
  const uint64_t complete_wrong = wrong_bits(lit, lit_counts);  // every row: the warp's own error
  input.row_valid = rows;
  const uint64_t lit_wrong = wrong_bits(lit, lit_counts);
  const uint64_t neighbour_wrong = wrong_bits(neighbours, neighbour_counts);
  const uint64_t older_wrong = wrong_bits(older_first, older_counts);
  std::printf("lost rows without shadow maps: all rows %llu wrong bits, lit %llu (%llu unfilled), neighbour fill %llu (%llu filled), "
              "previous buffer first %llu (%llu filled from it)\n",
              static_cast<unsigned long long>(complete_wrong), static_cast<unsigned long long>(lit_wrong),
              static_cast<unsigned long long>(lit_counts.unfilled()),
              static_cast<unsigned long long>(neighbour_wrong),
              static_cast<unsigned long long>(neighbour_counts.filled_neighbour),
              static_cast<unsigned long long>(older_wrong), static_cast<unsigned long long>(older_counts.filled_older));
  EXPECT_GT(lit_counts[WarpStatus::kMissingRow], 0u);
  EXPECT_GT(neighbour_counts.filled_neighbour, neighbour_counts[WarpStatus::kMissingRow] / 2);
  EXPECT_GT(older_counts.filled_older, older_counts[WarpStatus::kMissingRow] / 2);
  // The fills remove most of the error the lost rows add.
  ASSERT_GT(lit_wrong, complete_wrong + 50);
  EXPECT_LT((neighbour_wrong - std::min(neighbour_wrong, complete_wrong)) * 3, lit_wrong - complete_wrong);
  EXPECT_LT((older_wrong - std::min(older_wrong, complete_wrong)) * 3, lit_wrong - complete_wrong);
}

}  // namespace
}  // namespace dhr::render
