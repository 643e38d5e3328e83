// The visibility codec and reassembler on real traced buffers (Embree, living room or the default room):
// exact round trips over the wire format, and a lossy delivery that costs only the lost shards' rows.
#include "scene/camera_bookmarks.hpp"
#include "codec/codec.hpp"
#include "protocol/protocol.hpp"
#include "codec/reassembly.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>

namespace dhr::server {
namespace {

std::vector<VisibilityBuffer> traced_buffers(Extent eye) {
  std::string path = test::shared_data_path("scenes/living_room.glb");
  if (path.empty()) path = test::source_path(kDefaultScenePath);
  SceneLoadResult loaded = load_scene(path);
  EXPECT_TRUE(loaded) << loaded.error;
  std::vector<VisibilityBuffer> out;
  if (!loaded) return out;
  std::string error;
  const auto bookmarks = load_camera_bookmarks(camera_bookmarks_path(path), &error);
  EXPECT_TRUE(bookmarks) << error;
  if (!bookmarks) return out;
  TracerOptions options;
  options.threads = 2;
  EmbreeTracer tracer(*loaded.scene, options);
  const GuardBand guard = paper_guard_band(eye);
  for (const CameraBookmark& b : *bookmarks) {
    const View view{left_eye_pose(look_at_pose(b).value()), symmetric_fov(90.0, eye)};
    VisibilityBuffer vis;
    TraceStats stats;
    tracer.trace(Camera::with_guard_band(view, eye, guard), vis, stats);
    out.push_back(std::move(vis));
  }
  return out;
}

TEST(CodecRealBuffers, RoundTripThroughTheWireAndTheReassembler) {
  const auto buffers = traced_buffers({640, 360});
  ASSERT_FALSE(buffers.empty());
  uint64_t frame = 1;
  for (const VisibilityBuffer& b : buffers) {
    for (bool aligned : {false, true}) {
      EncodeOptions options;
      options.row_aligned = aligned;
      const auto shards = make_visibility_shards(b, frame, Eye::kLeft, View{}, options);
      ASSERT_FALSE(shards.empty());
      ReassemblerConfig config;
      config.width = b.width;
      config.height = b.height;
      config.light_count = b.light_count;
      VisibilityReassembler lossless(config), lossy(config);
      std::vector<uint8_t> lost_rows(b.height, 0);
      for (size_t i = 0; i < shards.size(); ++i) {
        const std::vector<uint8_t> bytes = encode_datagram(Datagram{1, static_cast<uint32_t>(i), shards[i]});
        ASSERT_FALSE(bytes.empty());
        ASSERT_LE(bytes.size(), kMaxDatagramSize);
        Datagram d;
        ASSERT_EQ(decode_datagram(bytes, d), DecodeError::kNone);
        const auto& shard = std::get<VisibilityShard>(d.message);
        lossless.insert(shard);
        if (i % 5 == 2) {  // lose every fifth shard
          const uint32_t first = shard.first_pixel, last = first + shard.pixel_count - 1;
          for (uint32_t y = first / b.width; y <= last / b.width; ++y) lost_rows[y] = 1;
        } else {
          lossy.insert(shard);
        }
      }
      const ReassembledFrame* full = lossless.latest_complete(Eye::kLeft);
      ASSERT_NE(full, nullptr);
      EXPECT_EQ(full->visibility.buffer, b);
      const ReassembledFrame* partial = lossy.latest(Eye::kLeft);
      ASSERT_NE(partial, nullptr);
      for (uint32_t y = 0; y < b.height; ++y) {
        ASSERT_EQ(partial->visibility.row_valid[y], lost_rows[y] ? 0 : 1) << "row " << y;
        if (!partial->visibility.row_valid[y]) continue;
        for (uint32_t x = 0; x < b.width; ++x) ASSERT_EQ(partial->visibility.buffer.get(x, y), b.get(x, y));
      }
    }
    ++frame;
  }
}

}  // namespace
}  // namespace dhr::server
