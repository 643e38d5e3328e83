// The whole per-eye pipeline (G-buffer -> warp -> shading) on the project's default scene, the
// offscreen PNG sink and the JSON-lines statistics. DISABLED_MeasurePassTimes prints per-pass GPU times
// (run it with --gtest_also_run_disabled_tests; docs/client.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <utility>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "client_test_helpers.hpp"
#include "image/png_reader.hpp"
#include "image/png_writer.hpp"
#include "scene/scene.hpp"
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/offscreen_sink.hpp"
#include "render/stats_jsonl.hpp"
#include "vulkan_test_fixture.hpp"

namespace dhr::render {
namespace {

namespace fs = std::filesystem;
using ClientEyePipelineTest = vk::test::VulkanTest;

constexpr GuardBand kGuard{4, 3};

Scene default_room() {
  const SceneLoadResult loaded = load_scene((fs::path(DHR_SOURCE_DIR) / kDefaultScenePath).string());
  if (!loaded) throw std::runtime_error(loaded.error);
  return *loaded.scene;
}

// The scene's "entrance_overview" bookmark with the simulated HMD's field of view.
View entrance_view() {
  View view;
  view.pose = test::look_at({0.0, 1.6, 1.35}, {-0.1, 0.5, -0.9});
  view.fov = Fov{-0.742f, 0.742f, 0.779f, -0.779f};
  return view;
}

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("dhr_client_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

// Per-pixel luma (0-255) of an RGBA8 readback.
std::vector<int> luma(const std::vector<uint8_t>& rgba) {
  std::vector<int> out(rgba.size() / 4);
  for (size_t i = 0; i < out.size(); ++i) out[i] = (rgba[i * 4] * 2 + rgba[i * 4 + 1] * 5 + rgba[i * 4 + 2]) / 8;
  return out;
}

struct Frame {
  const VisibilityBuffer* buffer = nullptr;
  uint32_t slot = 0;
};

EyeStats render_frame(vk::Context& ctx, EyePipeline& eye, const View& view, const VisibilityBuffer* buffer,
                      uint32_t slot) {
  VisibilityInput input;
  input.buffer = buffer;
  input.traced = Camera::with_guard_band(view, eye.extent(), kGuard);
  ctx.submit_and_wait([&](VkCommandBuffer cmd) { eye.record(cmd, slot, view, input); });
  return eye.read_stats(slot);
}

TEST_F(ClientEyePipelineTest, DefaultRoomWithHalfShadowedVisibilityGivesLitAndDarkPixels) {
  const Scene scene = default_room();
  const ClientScene gpu_scene(ctx(), scene);
  const Extent extent{160, 120};
  EyePipelineOptions options;
  options.warp_status = true;  // the light-visibility debug view below reads it
  EyePipeline eye(ctx(), gpu_scene, extent, options);
  const View view = entrance_view();

  // Frame 0: nothing received yet -> everything lit. Frame 1: the left half of the traced buffer is dark.
  const EyeStats first = render_frame(ctx(), eye, view, nullptr, 0);
  EXPECT_FALSE(first.visibility_used);
  EXPECT_EQ(first.warp[WarpStatus::kKnown], 0u);
  EXPECT_GT(first.warp[WarpStatus::kNoData], extent.width * extent.height / 2);
  const std::vector<int> all_lit = luma(read_rgba8(ctx(), eye.output()));

  const Camera traced = Camera::with_guard_band(view, extent, kGuard);
  VisibilityBuffer half = VisibilityBuffer::create(traced.extent.width, traced.extent.height,
                                                   static_cast<uint32_t>(scene.lights.size()));
  for (uint32_t y = 0; y < half.height; ++y) {
    for (uint32_t x = half.width / 2; x < half.width; ++x) half.set(x, y, half.light_bits());
  }
  const EyeStats second = render_frame(ctx(), eye, view, &half, 1);
  EXPECT_TRUE(second.visibility_used);
  EXPECT_EQ(second.unknown_pixels(), 0u);
  EXPECT_EQ(second.warp.surface() + second.warp[WarpStatus::kBackground], uint64_t{extent.width} * extent.height);
  EXPECT_GT(second.draws.meshes_drawn, 0u);
  if (second.gpu.valid) {
    EXPECT_GE(second.gpu.gbuffer_ms, 0.0);
    EXPECT_GE(second.gpu.total_ms, second.gpu.gbuffer_ms);
  }

  const std::vector<int> shaded = luma(read_rgba8(ctx(), eye.output()));
  size_t lit = 0, dark = 0;
  for (uint32_t y = 0; y < extent.height; ++y) {
    for (uint32_t x = 0; x < extent.width; ++x) {
      const size_t p = size_t{y} * extent.width + x;
      if (x < extent.width / 2) {
        ASSERT_LE(shaded[p], all_lit[p]);
        if (shaded[p] < 12) ++dark;
      } else {
        ASSERT_EQ(shaded[p], all_lit[p]);
        if (shaded[p] > 60) ++lit;
      }
    }
  }
  EXPECT_GT(lit, size_t{extent.width} * extent.height / 8) << "lit pixels";
  EXPECT_GT(dark, size_t{extent.width} * extent.height / 8) << "dark pixels";

  // The PNG sink writes what was shaded.
  const fs::path dir = temp_dir("png");
  OffscreenPngSink sink(ctx(), dir.string(), 2);
  EXPECT_FALSE(sink.write(1, 0, eye.output()).has_value());  // every 2nd frame only
  const std::optional<std::string> path = sink.write(2, 1, eye.output());
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(fs::path(*path).filename().string(), "frame_000002_right.png");
  std::ifstream file(*path, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 100u);
  EXPECT_EQ(std::string(bytes.data() + 1, 3), "PNG");
  EXPECT_EQ(sink.files_written(), 1u);
  // Its pixels are the image's; a sink for images shaded for a BGRA swapchain swaps red and blue back.
  const std::vector<uint8_t> rgba = read_rgba8(ctx(), eye.output());
  std::string png_error;
  const auto png = dhr::read_png_rgb(*path, &png_error);
  ASSERT_TRUE(png) << png_error;
  OffscreenPngSink swapping(ctx(), (dir / "swapped").string(), 1, /*swap_red_blue=*/true);
  const auto swapped = dhr::read_png_rgb(*swapping.write(2, 1, eye.output()), &png_error);
  ASSERT_TRUE(swapped) << png_error;
  size_t coloured = 0;
  for (size_t i = 0; i < rgba.size() / 4; ++i) {
    ASSERT_EQ(png->rgb[i * 3], rgba[i * 4]);
    ASSERT_EQ(png->rgb[i * 3 + 2], rgba[i * 4 + 2]);
    ASSERT_EQ(swapped->rgb[i * 3], rgba[i * 4 + 2]);
    ASSERT_EQ(swapped->rgb[i * 3 + 1], rgba[i * 4 + 1]);
    ASSERT_EQ(swapped->rgb[i * 3 + 2], rgba[i * 4]);
    if (rgba[i * 4] != rgba[i * 4 + 2]) ++coloured;
  }
  EXPECT_GT(coloured, 0u) << "the swap must be visible somewhere";
  fs::remove_all(dir);

  // DHR_TEST_PNG_DIR=<dir>: keep PNGs of this frame and its debug views for people to look at.
  if (const char* keep = std::getenv("DHR_TEST_PNG_DIR")) {
    OffscreenPngSink keep_sink(ctx(), keep, 1);
    const std::pair<ShadingView, const char*> views[] = {{ShadingView::kShaded, "shaded"},
                                                         {ShadingView::kLightVisibility, "light0"},
                                                         {ShadingView::kAlbedo, "albedo"},
                                                         {ShadingView::kNormal, "normal"}};
    uint64_t frame = 0;
    for (const auto& [mode, name] : views) {
      eye.shading().view = mode;
      render_frame(ctx(), eye, view, &half, 0);
      const std::string written = *keep_sink.write(frame++, 0, eye.output());
      std::printf("%s: %s\n", name, written.c_str());
    }
  }
}

TEST_F(ClientEyePipelineTest, FramesInFlightResizeAndStatsLines) {
  const Scene scene = default_room();
  const ClientScene gpu_scene(ctx(), scene);
  EyePipelineOptions options;
  options.frames_in_flight = 2;
  options.motion_vectors = true;
  EyePipeline eye(ctx(), gpu_scene, Extent{96, 72}, options);
  EXPECT_FALSE(eye.read_stats(1).gpu.valid);  // never recorded
  View view = entrance_view();
  const Camera traced = Camera::with_guard_band(view, eye.extent(), kGuard);
  const VisibilityBuffer vis = VisibilityBuffer::create(traced.extent.width, traced.extent.height, 3);

  // Two frames recorded back to back into one submission, one per slot, the second with a moved head.
  VisibilityInput input{&vis, traced, {}, 1};
  View moved = view;
  moved.pose = test::rotated(view.pose, 4.0, 0.0);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    eye.record(cmd, 0, view, input);
    eye.record(cmd, 1, moved, input);
  });
  const EyeStats a = eye.read_stats(0), b = eye.read_stats(1);
  EXPECT_EQ(a.warp.unknown_surface(), 0u);
  EXPECT_GT(b.warp[WarpStatus::kOutside], 0u);
  EXPECT_EQ(a.warp.surface() + a.warp[WarpStatus::kBackground], 96u * 72u);
  EXPECT_EQ(b.warp.surface() + b.warp[WarpStatus::kBackground], 96u * 72u);

  eye.resize(Extent{64, 48});
  EXPECT_EQ(eye.output().width(), 64u);
  const EyeStats c = render_frame(ctx(), eye, view, nullptr, 0);
  EXPECT_EQ(c.extent, (Extent{64, 48}));
  EXPECT_EQ(c.warp.surface() + c.warp[WarpStatus::kBackground], 64u * 48u);

  const fs::path dir = temp_dir("jsonl");
  fs::create_directories(dir);
  {
    JsonLinesWriter writer((dir / "stats.jsonl").string());
    writer.write(eye_stats_json(7, 0, b));
    writer.write(eye_stats_json(8, 1, c));
    EXPECT_EQ(writer.lines(), 2u);
    EXPECT_THROW(writer.write("{\n}"), std::invalid_argument);
  }
  std::ifstream in(dir / "stats.jsonl");
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line.rfind("{\"frame\":7,\"eye\":0,\"width\":96,\"height\":72,", 0), 0u) << line;
  EXPECT_NE(line.find("\"outside\":"), std::string::npos);
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_NE(line.find("\"no_data\":"), std::string::npos);
  EXPECT_THROW(JsonLinesWriter((dir / "missing" / "x.jsonl").string()), std::runtime_error);
  fs::remove_all(dir);
}

TEST_F(ClientEyePipelineTest, PngWriterRejectsBadInput) {
  const std::vector<uint8_t> pixels(4 * 3 * 3, 128);
  const fs::path dir = temp_dir("pngw");
  fs::create_directories(dir);
  EXPECT_FALSE(write_png((dir / "ok.png").string(), 4, 3, 3, pixels).has_value());
  EXPECT_TRUE(write_png((dir / "bad.png").string(), 4, 4, 3, pixels).has_value());
  EXPECT_TRUE(write_png((dir / "bad.png").string(), 4, 3, 5, pixels).has_value());
  EXPECT_TRUE(write_png((dir / "no" / "dir.png").string(), 4, 3, 3, pixels).has_value());
  fs::remove_all(dir);
}

// Per-pass GPU time (median of 15 frames) of the default scene and, when ../shared/data is there, of its living_room.glb
// (163k triangles), at the simulated HMD's size and at 1832x1920. Not a test of timings: it prints JSON lines.
TEST_F(ClientEyePipelineTest, DISABLED_MeasurePassTimes) {
  struct Case {
    std::string name;
    fs::path path;
    View view;
  };
  std::vector<Case> cases = {{"default_room", fs::path(DHR_SOURCE_DIR) / kDefaultScenePath, entrance_view()}};
  const fs::path living_room = fs::path(DHR_SOURCE_DIR) / "../shared/data/scenes/living_room.glb";
  if (fs::exists(living_room)) {
    View doorway = entrance_view();
    doorway.pose = test::look_at({2.55, 1.6, 1.7}, {-0.8, 0.55, -1.3});  // its "doorway_overview" bookmark
    cases.push_back({"living_room", living_room, doorway});
  }
  for (const Case& c : cases) {
    const SceneLoadResult loaded = load_scene(c.path.string());
    ASSERT_TRUE(loaded.ok()) << loaded.error;
    const Scene& scene = *loaded.scene;
    const ClientScene gpu_scene(ctx(), scene);
    for (const Extent extent : {Extent{320, 240}, Extent{1832, 1920}}) {
      EyePipeline eye(ctx(), gpu_scene, extent);
      const Camera traced =
          Camera::with_guard_band(c.view, extent, paper_guard_band(extent));
      VisibilityBuffer vis = VisibilityBuffer::create(traced.extent.width, traced.extent.height,
                                                      static_cast<uint32_t>(scene.lights.size()));
      for (size_t p = 0; p < vis.pixel_count(); ++p) {
        vis.set_mask_at(p, static_cast<uint32_t>(p * 2654435761u) & vis.light_bits());
      }
      View moved = c.view;
      moved.pose = test::rotated(c.view.pose, 1.0, 0.5);  // a small head motion since the trace
      const VisibilityInput input{&vis, traced, {}, 1};
      std::vector<EyeStats> runs;
      for (int i = 0; i < 16; ++i) {
        ctx().submit_and_wait([&](VkCommandBuffer cmd) { eye.record(cmd, 0, moved, input); });
        if (i > 0) runs.push_back(eye.read_stats(0));  // the first run warms caches up
      }
      ASSERT_TRUE(runs.back().gpu.valid);
      auto median = [&](double EyePassTimes::*field) {
        std::vector<double> v;
        for (const EyeStats& s : runs) v.push_back(s.gpu.*field);
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
      };
      std::printf("{\"device\":\"%s\",\"scene\":\"%s\",\"triangles\":%llu,\"width\":%u,\"height\":%u,"
                  "\"runs\":%zu,\"gbuffer_ms\":%.3f,\"warp_ms\":%.3f,\"shading_ms\":%.3f,"
                  "\"total_ms\":%.3f}\n",
                  ctx().info().name.c_str(), c.name.c_str(), static_cast<unsigned long long>(gpu_scene.triangle_count()),
                  extent.width, extent.height, runs.size(), median(&EyePassTimes::gbuffer_ms),
                  median(&EyePassTimes::warp_ms), median(&EyePassTimes::shading_ms),
                  median(&EyePassTimes::total_ms));
    }
  }
}

}  // namespace
}  // namespace dhr::render
