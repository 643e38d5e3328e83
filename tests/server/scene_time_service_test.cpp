// VisibilityService and scene time (DESIGN 5b): a moving scene is traced at each pose's scene time (plus the
// horizon when predicting), every shard names the scene time its eye was traced for, the same pose at the same
// scene time gives the same bits, and a static scene is never moved. The moving scene is a small glTF written here
// (tests/common/test_gltf.hpp): a floor, an occluder on an animated node sliding over it, a point light above.
#include "service_test_rig.hpp"
#include "test_gltf.hpp"

#include <nlohmann/json.hpp>

namespace dhr::server {
namespace {

using namespace test_rig;
using nlohmann::json;

// A 8 m x 8 m floor (y = 0, facing +y), a 1 m x 1 m double-sided occluder at y = 1 on node 1, which slides along x
// from -1.5 (t = 0) to +1.5 (t = 2 s), and a point light at (0, 3, 0).
std::string sliding_occluder_gltf() {
  test::TestGltf g;
  const auto quad = [&](float half, float y, int material) {
    const int pos = g.floats({-half, y, -half, -half, y, half, half, y, half, half, y, -half}, "VEC3", 3);
    const std::vector<uint16_t> indices = {0, 1, 2, 0, 2, 3};
    const int idx = g.accessor(indices.data(), indices.size() * 2, 5123, indices.size(), "SCALAR");
    const json primitive = {{"attributes", {{"POSITION", pos}}}, {"indices", idx}, {"material", material}};
    g.doc["meshes"].push_back({{"primitives", json::array({primitive})}});
    return static_cast<int>(g.doc["meshes"].size()) - 1;
  };
  g.doc["materials"] = json::array({{{"doubleSided", false}}, {{"doubleSided", true}}});
  g.node({{"mesh", quad(4.0f, 0.0f, 0)}});                                         // 0: the floor
  g.node({{"mesh", quad(0.5f, 0.0f, 1)}, {"translation", {-1.5, 1.0, 0.0}}});  // 1: the occluder
  g.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({{{"type", "point"}, {"intensity", 20}}});
  g.doc["extensionsUsed"] = json::array({"KHR_lights_punctual"});
  g.node({{"translation", {0, 3, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});  // 2: the light
  const int times = g.floats({0.0f, 2.0f}, "SCALAR", 1);
  const int values = g.floats({-1.5f, 1.0f, 0.0f, 1.5f, 1.0f, 0.0f}, "VEC3", 3);
  g.doc["animations"] = json::array(
      {{{"name", "slide"},
        {"samplers", json::array({{{"input", times}, {"output", values}, {"interpolation", "LINEAR"}}})},
        {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}}})}}});
  return g.text({0, 1, 2});
}

SharedScene& sliding_occluder_scene() { return shared_scene_from_text("sliding.gltf", sliding_occluder_gltf()); }

class SceneTimeServiceTest : public VisibilityServiceTest {
 protected:
  void SetUp() override {
    config_.skip_identical_pose = true;
    serve("sliding", sliding_occluder_scene(), 7);
  }

  void send_pose_at(uint64_t token, uint64_t frame, int64_t scene_time_ns) {
    send_pose(token, peer(1), frame, floor_views(), scene_time_ns);
  }

  // Traces what is pending and returns the frame's shards (every one checked to name `frame`).
  std::vector<VisibilityShard> trace_frame(uint64_t frame) {
    EXPECT_EQ(service_->process_pending(), 1u);
    std::vector<VisibilityShard> shards = shards_of(drain()[peer(1)]);
    EXPECT_FALSE(shards.empty());
    for (const VisibilityShard& s : shards) EXPECT_EQ(s.frame_number, frame);
    return shards;
  }

  static void expect_scene_time(const std::vector<VisibilityShard>& shards, int64_t scene_time_ns) {
    for (const VisibilityShard& s : shards) EXPECT_EQ(s.scene_time_ns, scene_time_ns);
  }
};

TEST_F(SceneTimeServiceTest, TheSceneIsTracedAtThePosesSceneTime) {
  ASSERT_TRUE(scene_->tracer->moves());
  Welcome w;
  const uint64_t t = connect(peer(1), 1, &w);
  ASSERT_NE(t, 0u);

  send_pose_at(t, 1, 0);
  const auto at_rest = trace_frame(1);
  expect_scene_time(at_rest, 0);
  // The same views one second later: the occluder stands over the floor's centre, its shadow elsewhere.
  send_pose_at(t, 2, net::kNsPerSecond);
  const auto at_one = trace_frame(2);
  expect_scene_time(at_one, net::kNsPerSecond);
  // Back at scene time 0: the same bits as the first frame (deterministic; not skipped as identical, since the
  // last traced pose was at another scene time).
  send_pose_at(t, 3, 0);
  const auto again = trace_frame(3);
  expect_scene_time(again, 0);

  const auto a = reassemble(w, at_rest, 1), b = reassemble(w, at_one, 2), c = reassemble(w, again, 3);
  for (size_t e = 0; e < 2; ++e) {
    EXPECT_NE(a[e].data, b[e].data) << "eye " << e;
    EXPECT_EQ(a[e].data, c[e].data) << "eye " << e;
  }
  // What the service traced equals the tracer moved to those times by hand.
  const std::array<View, 2> views = floor_views();
  for (const auto& [seconds, expected] : {std::pair{0.0, &a}, std::pair{1.0, &b}}) {
    scene_->tracer->set_scene_time(seconds);
    VisibilityBuffer direct;
    TraceStats stats;
    scene_->tracer->trace(w.format().camera(view_as_decoded(views[0]).value()), direct, stats);
    EXPECT_EQ(direct.data, (*expected)[0].data) << "scene time " << seconds;
  }
  scene_->tracer->set_scene_time(0.0);

  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.frames_traced, 3u);
  EXPECT_EQ(s.frames_at_scene_time, 3u);
  EXPECT_GE(s.scene_update_ms, 0.0);
  EXPECT_EQ(s.poses_skipped_identical, 0u);
  const auto j = to_json(s);
  EXPECT_EQ(j["frames_at_scene_time"], 3u);
  EXPECT_TRUE(j.contains("scene_update_ms"));
  EXPECT_TRUE(j.contains("scene_update_ms_per_frame"));
}

TEST_F(SceneTimeServiceTest, AnIdenticalPoseAtTheSameSceneTimeIsSkipped) {
  const uint64_t t = connect(peer(1), 1);
  send_pose_at(t, 1, 250'000'000);
  trace_frame(1);
  send_pose_at(t, 2, 250'000'000);
  EXPECT_EQ(service_->process_pending(), 0u);
  EXPECT_EQ(service_->stats().poses_skipped_identical, 1u);
}

TEST_F(SceneTimeServiceTest, PredictionTracesThePosesSceneTimePlusTheHorizon) {
  config_.predict = true;
  config_.predict_horizon_ns = 20'000'000;
  make_service();
  const uint64_t t = connect(peer(1), 1);
  send_pose_at(t, 1, 500'000'000);
  expect_scene_time(trace_frame(1), 520'000'000);
  send_pose_at(t, 2, 511'000'000);
  expect_scene_time(trace_frame(2), 531'000'000);
  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.frames_predicted, 2u);
  EXPECT_EQ(s.frames_at_scene_time, 2u);
}

// The default room has no animation: nothing moves, and the shards still name the pose's scene time.
TEST_F(VisibilityServiceTest, AStaticSceneIsNotMovedAndShardsNameThePosesSceneTime) {
  ASSERT_FALSE(scene_->tracer->moves());
  const uint64_t t = connect(peer(1), 1);
  PoseUpdate p;
  p.frame = 1;
  p.display_time_ns = 11'000'000;
  p.scene_time_ns = 4'000'000'000;
  p.views = bookmark_views(0);
  send(Datagram{t, 1, p}, peer(1));
  EXPECT_EQ(service_->process_pending(), 1u);
  const auto shards = shards_of(drain()[peer(1)]);
  ASSERT_FALSE(shards.empty());
  for (const VisibilityShard& s : shards) EXPECT_EQ(s.scene_time_ns, 4'000'000'000);
  EXPECT_EQ(service_->stats().frames_at_scene_time, 0u);
  EXPECT_EQ(service_->stats().scene_update_ms, 0.0);
}

// A client of protocol version 4 (no scene time), 5 (no NodeTransform) or 6 (codec v2's earlier contexts, whose
// shards it could not decode) gets the version mismatch answer, as any other version does.
TEST_F(VisibilityServiceTest, AVersion6HelloGetsByeVersionMismatch) {
  std::vector<uint8_t> old = encode_datagram(Datagram{0, 0, make_hello(5)});
  ASSERT_EQ(kProtocolVersion, 7);
  old[4] = 6;
  send_raw(old, peer(3));
  const auto byes = byes_of(drain()[peer(3)]);
  ASSERT_EQ(byes.size(), 1u);
  EXPECT_EQ(byes[0].reason, ByeReason::kVersionMismatch);
  EXPECT_EQ(service_->stats().wrong_version, 1u);
  EXPECT_EQ(service_->session_count(), 0u);
}

}  // namespace
}  // namespace dhr::server
