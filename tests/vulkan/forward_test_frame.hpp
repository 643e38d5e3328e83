// The forward-pass tests' frame (client_forward_test.cpp, client_forward_depth_test.cpp): the default room, a
// traced view and a display view 3 cm to the right and turned, visibility patterns with structure at several
// scales, and a run of the forward pass that reads back every target.
#pragma once
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "client_test_helpers.hpp"
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/forward_pass.hpp"
#include "render/offscreen_sink.hpp"
#include "render/shadow_maps.hpp"
#include "render/warp_reference.hpp"
#include "scene/scene.hpp"
#include "vk/context.hpp"
#include "vk/image.hpp"

namespace dhr::render::forward_test {

namespace fs = std::filesystem;

constexpr Extent kExtent{160, 120};
constexpr GuardBand kGuard{4, 3};
constexpr double kNear = kDefaultNearPlane;
constexpr double kMargin = 2e-3;  // pixels: decisions closer to a flip are not compared (warp_reference.hpp)

inline Scene default_room() {
  const SceneLoadResult loaded = load_scene((fs::path(DHR_SOURCE_DIR) / kDefaultScenePath).string());
  if (!loaded) throw std::runtime_error(loaded.error);
  return *loaded.scene;
}

// The project's area-light room (a rect and a sphere light with soft fields, one hard light).
inline Scene default_room_area() {
  const SceneLoadResult loaded =
      load_scene((fs::path(DHR_SOURCE_DIR) / "assets/scenes/default_room_area.gltf").string());
  if (!loaded) throw std::runtime_error(loaded.error);
  return *loaded.scene;
}

// A buffer for `traced` in `layout` whose light i at pixel (x, y) has the share share(x, y, i) (a hard light's bit
// set where it is >= 0.5, a soft light's nearest level).
template <class Share>
VisibilityBuffer buffer_of_shares(const Camera& traced, const VisibilityLayout& layout, Share share) {
  VisibilityBuffer b = VisibilityBuffer::create(traced.extent.width, traced.extent.height, layout.total_bits());
  for (uint32_t y = 0; y < b.height; ++y) {
    for (uint32_t x = 0; x < b.width; ++x) {
      uint32_t m = 0;
      for (uint32_t i = 0; i < layout.light_count; ++i) m = layout.with_visibility(m, i, share(x, y, i));
      b.set(x, y, m);
    }
  }
  return b;
}

inline View traced_view() {
  View view;
  view.pose = test::look_at({0.0, 1.6, 1.35}, {-0.1, 0.5, -0.9});
  view.fov = Fov{-0.742f, 0.742f, 0.779f, -0.779f};
  return view;
}

// The head 3 cm to the right and turned 4 degrees left, 2 up: lookups land between old pixels, some outside.
inline View display_view() {
  View view = traced_view();
  view.pose.position += glm::dvec3(0.03, 0.0, 0.0);
  view.pose = test::rotated(view.pose, 4.0, 2.0);
  return view;
}

// Bits with structure at several scales, so that where a pixel looks up matters.
inline VisibilityBuffer patterned(const Camera& traced, uint32_t lights) {
  VisibilityBuffer b = VisibilityBuffer::create(traced.extent.width, traced.extent.height, lights);
  for (uint32_t y = 0; y < b.height; ++y) {
    for (uint32_t x = 0; x < b.width; ++x) {
      uint32_t m = 0;
      if (((x / 3) + (y / 5)) % 2 == 0) m |= 1u;
      if (x > b.width / 2) m |= 2u;
      if ((x * 7 + y * 3) % 11 < 6) m |= 4u;
      b.set(x, y, m & b.light_bits());
    }
  }
  return b;
}

// Bits in blocks and stripes several pixels wide: the 2x2 samples agree inside them and disagree on their edges.
inline VisibilityBuffer blocky(const Camera& traced, uint32_t lights) {
  VisibilityBuffer b = VisibilityBuffer::create(traced.extent.width, traced.extent.height, lights);
  for (uint32_t y = 0; y < b.height; ++y) {
    for (uint32_t x = 0; x < b.width; ++x) {
      uint32_t m = 0;
      if (((x / 8) + (y / 6)) % 2 == 0) m |= 1u;
      if (x > b.width / 2) m |= 2u;
      if (((x + y) / 12) % 2 == 0) m |= 4u;
      b.set(x, y, m & b.light_bits());
    }
  }
  return b;
}

// The warp tests' frame: this eye's buffer traced for traced_view(), rows 40-47 lost (their lookups are unknown),
// the display view. Holds what the frame points to, so it is neither copied nor moved.
struct ForwardTestFrame {
  ForwardTestFrame(const Scene& scene, VisibilityBuffer (*bits)(const Camera&, uint32_t), const ShadowMaps* maps = nullptr)
      : traced(Camera::with_guard_band(traced_view(), kExtent, kGuard)),
        buffer(bits(traced, static_cast<uint32_t>(scene.lights.size()))),
        rows(traced.extent.height, 1) {
    for (uint32_t r = 40; r < 48; ++r) rows[r] = 0;
    input.buffer = &buffer;
    input.traced = traced;
    input.row_valid = rows;
    view = display_view();
    frame.display = display_camera(view, kExtent);
    frame.near_plane = kNear;
    frame.visibility = &input;
    frame.shadow_maps = maps;
    frame.lights = scene.lights;
  }
  ForwardTestFrame(const ForwardTestFrame&) = delete;
  // The CPU reference's input for this frame over the display's `depth`: source 0 and the lights as the frame's
  // (the caller adds normals, settings and shadow maps where the warp needs them).
  WarpInput reference_input(std::span<const float> depth) const {
    WarpInput in;
    in.depth = depth;
    in.display = frame.display;
    in.near_plane = kNear;
    in.sources[0].traced = traced;
    in.sources[0].visibility = &buffer;
    in.sources[0].row_valid = input.row_valid;
    in.lights = frame.lights;
    return in;
  }
  ForwardTestFrame& operator=(const ForwardTestFrame&) = delete;

  Camera traced;
  VisibilityBuffer buffer;
  std::vector<uint8_t> rows;
  VisibilityInput input;
  View view;
  ForwardFrame frame;
};

// The deferred pipeline's options the forward pass is compared with: compute warp and shading with `settings`,
// the warp's status written.
inline EyePipelineOptions deferred_options(const WarpSettings& settings) {
  EyePipelineOptions options;
  options.forward = false;
  options.warp_status = true;
  options.warp = settings;
  return options;
}

struct ForwardResult {
  std::vector<float> depth;
  std::vector<uint8_t> colour;
  std::vector<uint32_t> status;
  std::vector<uint32_t> mask;
  WarpCounts counts;
};

inline ForwardResult run_forward(vk::Context& ctx, const ClientScene& scene, ForwardMode mode, const ForwardFrame& frame) {
  ForwardOptions options;
  options.mode = mode;
  options.write_mask = true;
  ForwardPass pass(ctx, scene, options);
  ForwardTargets targets = ForwardTargets::create(ctx, kExtent, options);
  ctx.submit_and_wait([&](VkCommandBuffer cmd) { pass.record(cmd, 0, frame, targets); });
  ForwardResult out;
  out.depth = test::read_pixels<float>(ctx, targets.depth);
  out.colour = read_rgba8(ctx, targets.colour);
  if (targets.has_status()) {
    const std::vector<uint8_t> status = test::read_pixels<uint8_t>(ctx, targets.status);
    out.status.assign(status.begin(), status.end());
  }
  out.mask = test::read_pixels<uint32_t>(ctx, targets.mask);
  out.counts = pass.read_counts(0);
  return out;
}

// The client's shadow maps as the CPU reference reads them; `storage` holds the atlas's texels.
inline ShadowReference shadow_reference(const vk::Context& ctx, const ShadowMaps& maps, std::vector<float>& storage) {
  vk::Image& atlas = const_cast<ShadowMaps&>(maps).atlas();  // read only: read_image takes the image by reference
  storage.resize(size_t{atlas.width()} * atlas.height());
  vk::read_image(ctx, atlas, storage.data(), storage.size() * sizeof(float));
  ShadowReference ref;
  ref.atlas = storage;
  ref.face_size = maps.face_size();
  ref.tiles = maps.tiles();
  ref.settings = maps.settings();
  return ref;
}

// A scene on the GPU, its shadow maps and their CPU reference, and the warp tests' frame over `bits`. Neither
// copied nor moved (the frame and the reference point into it).
struct SceneRig {
  SceneRig(vk::Context& ctx, Scene s, VisibilityBuffer (*bits)(const Camera&, uint32_t))
      : scene(std::move(s)),
        gpu_scene(ctx, scene),
        maps(ctx, gpu_scene),
        shadow(shadow_reference(ctx, maps, atlas_storage)),
        warp(scene, bits, &maps) {}
  SceneRig(const SceneRig&) = delete;
  SceneRig& operator=(const SceneRig&) = delete;

  const Scene scene;
  const ClientScene gpu_scene;
  ShadowMaps maps;
  std::vector<float> atlas_storage;  // the atlas's texels, which `shadow` reads
  const ShadowReference shadow;
  const ForwardTestFrame warp;
};

// The depth tests' set-up: the default room over blocky bits.
struct DefaultRoomRig : SceneRig {
  explicit DefaultRoomRig(vk::Context& ctx) : SceneRig(ctx, default_room(), blocky) {}
};

}  // namespace dhr::render::forward_test
