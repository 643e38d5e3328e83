// VisibilityService and app-moved nodes (docs/motion.md, "App-moved nodes"): a client's NodeTransform moves a node
// the scene marks movable from its scene time on, every later frame is traced with it (equal to a fresh build of
// scene_at with the same transforms), and transforms that cannot take effect are dropped and counted: for an
// unknown node, out of order, late. The scene: tests/common/test_movable_scene.hpp (a floor, a movable occluder,
// a point light above).
#include "scene/node_overrides.hpp"
#include "scene/scene_at.hpp"
#include "service_test_rig.hpp"
#include "test_movable_scene.hpp"

#include <nlohmann/json.hpp>

namespace dhr::server {
namespace {

using namespace test_rig;

using test::kFloorNode;
using test::kOccluderNode;
using test::movable_occluder_gltf;
using test::occluder_at;
constexpr int64_t kMs = 1'000'000;

SharedScene& movable_occluder_scene() { return shared_scene_from_text("movable.gltf", movable_occluder_gltf()); }

class NodeTransformServiceTest : public VisibilityServiceTest {
 protected:
  void SetUp() override {
    serve("movable", movable_occluder_scene(), 9);
    token_ = connect(peer(1), 1, &welcome_);
    ASSERT_NE(token_, 0u);
  }
  void TearDown() override { scene_->tracer->set_scene_time(0.0); }

  void send_pose_at(uint64_t frame, int64_t scene_time_ns) {
    send_pose(token_, peer(1), frame, floor_views(), scene_time_ns);
  }
  // Sends it and returns it as the server decodes it (what the client records).
  NodeTransform move(uint32_t node, int64_t scene_time_ns, const Trs& trs) {
    const NodeTransform sent = node_transform_as_decoded(NodeTransform{node, scene_time_ns, trs}).value();
    send(Datagram{token_, ++sequence_, sent}, peer(1));
    return sent;
  }
  std::array<VisibilityBuffer, 2> trace_frame(uint64_t frame) {
    EXPECT_EQ(service_->process_pending(), 1u);
    return reassemble(welcome_, shards_of(drain()[peer(1)]), frame);
  }
  // The exhaustive reference: a fresh tracer on scene_at(scene, t, overrides), left eye.
  VisibilityBuffer reference(double t, const NodeOverrides& overrides) {
    TracerOptions options;
    options.threads = 2;
    EmbreeTracer fresh(scene_at(scene_->scene, t, &overrides), options);
    VisibilityBuffer out;
    TraceStats stats;
    fresh.trace(welcome_.format().camera(view_as_decoded(floor_views()[0]).value()), out, stats);
    return out;
  }

  uint64_t token_ = 0;
  uint32_t sequence_ = 100;
  Welcome welcome_;
};

TEST_F(NodeTransformServiceTest, AMovableNodeIsTracedWhereTheAppPutIt) {
  ASSERT_TRUE(scene_->tracer->moves());  // the movable node alone makes the scene move
  ASSERT_NE(scene_->scene.animation.find(kOccluderNode), nullptr);
  send_pose_at(1, 100 * kMs);
  const auto at_rest = trace_frame(1);
  NodeOverrides overrides;  // what the client records
  const NodeTransform t = move(kOccluderNode, 150 * kMs, occluder_at(1.5));
  ASSERT_EQ(overrides.add(scene_->scene.animation, t.node, t.scene_time_ns, t.trs), NodeTransformVerdict::kAccepted);
  send_pose_at(2, 200 * kMs);
  const auto moved = trace_frame(2);
  EXPECT_NE(at_rest[0].data, moved[0].data);
  EXPECT_EQ(moved[0].data, reference(0.2, overrides).data);
  EXPECT_EQ(at_rest[0].data, reference(0.1, NodeOverrides{}).data);

  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.node_transforms_received, 1u);
  EXPECT_EQ(s.node_transforms_applied, 1u);
  const auto j = to_json(s);
  EXPECT_EQ(j["node_transforms_applied"], 1u);
  EXPECT_EQ(j["node_transforms_dropped_late"], 0u);
}

TEST_F(NodeTransformServiceTest, BeyondTheNewestTheServerExtrapolates) {
  NodeOverrides overrides;
  for (const auto& [stamp, x] : {std::pair{100 * kMs, -1.0}, std::pair{200 * kMs, -0.5}}) {
    const NodeTransform t = move(kOccluderNode, stamp, occluder_at(x));
    ASSERT_EQ(overrides.add(scene_->scene.animation, t.node, t.scene_time_ns, t.trs), NodeTransformVerdict::kAccepted);
  }
  // 0.2 s past the newest: 5 m/s more along x, 1 m further (inside the 0.25 s horizon).
  send_pose_at(1, 400 * kMs);
  const auto traced = trace_frame(1);
  EXPECT_NEAR(overrides.trs_at(kOccluderNode, 0.4)->translation.x, 0.5, 1e-9);
  EXPECT_EQ(traced[0].data, reference(0.4, overrides).data);
}

TEST_F(NodeTransformServiceTest, UnknownOutOfOrderAndLateTransformsAreDroppedAndCounted) {
  move(kFloorNode, 100 * kMs, occluder_at(0.0));  // a node the scene does not let move
  move(77, 100 * kMs, occluder_at(0.0));          // no such node
  move(kOccluderNode, 300 * kMs, occluder_at(0.0));
  move(kOccluderNode, 300 * kMs, occluder_at(1.0));  // the same stamp again
  move(kOccluderNode, 250 * kMs, occluder_at(1.0));  // older than the newest
  send_pose_at(1, 500 * kMs);
  trace_frame(1);
  move(kOccluderNode, 450 * kMs, occluder_at(1.0));  // before the scene time already traced: late
  move(kOccluderNode, 500 * kMs, occluder_at(1.0));  // at it: still in time
  const ServiceStats s = service_->stats();
  EXPECT_EQ(s.node_transforms_received, 7u);
  EXPECT_EQ(s.node_transforms_applied, 2u);
  EXPECT_EQ(s.node_transforms_dropped_unknown_node, 2u);
  EXPECT_EQ(s.node_transforms_dropped_out_of_order, 2u);
  EXPECT_EQ(s.node_transforms_dropped_late, 1u);
  EXPECT_EQ(s.datagrams_rejected, 0u);  // well-formed: dropped for what they ask, not as bad datagrams
  const auto j = to_json(s);
  EXPECT_EQ(j["node_transforms_dropped_unknown_node"], 2u);
  EXPECT_EQ(j["node_transforms_dropped_out_of_order"], 2u);
  EXPECT_EQ(j["node_transforms_dropped_late"], 1u);
}

// With prediction the frame is traced at the pose's scene time plus the horizon: a transform stamped within the
// horizon is news about a guessed time, not late.
TEST_F(NodeTransformServiceTest, LateIsMeasuredAgainstThePosesSceneTimeNotThePredictedOne) {
  config_.predict = true;
  config_.predict_horizon_ns = 100 * kMs;
  make_service();
  token_ = connect(peer(1), 2, &welcome_);
  send_pose_at(1, 500 * kMs);
  trace_frame(1);  // traced at 0.6 s
  move(kOccluderNode, 550 * kMs, occluder_at(1.0));
  EXPECT_EQ(service_->stats().node_transforms_applied, 1u);
  EXPECT_EQ(service_->stats().node_transforms_dropped_late, 0u);
}

// A pose identical to the last traced one, at the same scene time, is traced again when a transform arrived since.
TEST_F(NodeTransformServiceTest, ANewTransformMakesAnIdenticalPoseWorthTracing) {
  config_.skip_identical_pose = true;
  make_service();
  token_ = connect(peer(1), 3, &welcome_);
  send_pose_at(1, 200 * kMs);
  trace_frame(1);
  send_pose_at(2, 200 * kMs);
  EXPECT_EQ(service_->process_pending(), 0u);  // identical: skipped
  drain();
  move(kOccluderNode, 200 * kMs, occluder_at(0.0));
  send_pose_at(3, 200 * kMs);
  EXPECT_EQ(service_->process_pending(), 1u);
  EXPECT_EQ(service_->stats().poses_skipped_identical, 1u);
}

// Determinism of the scene clock: two sessions sent the same poses and transforms get the same bits, and the same
// scene time traced again gives the first bits.
TEST_F(NodeTransformServiceTest, TheSameInputsGiveTheSameBits) {
  std::array<VisibilityBuffer, 2> first;
  for (int run = 0; run < 2; ++run) {
    make_service();
    token_ = connect(peer(1), 10 + static_cast<uint64_t>(run), &welcome_);
    move(kOccluderNode, 100 * kMs, occluder_at(-1.0));
    move(kOccluderNode, 130 * kMs, occluder_at(-0.7));
    send_pose_at(1, 250 * kMs);
    const auto a = trace_frame(1);
    send_pose_at(2, 120 * kMs);
    trace_frame(2);
    send_pose_at(3, 250 * kMs);
    const auto again = trace_frame(3);
    EXPECT_EQ(a[0].data, again[0].data);
    EXPECT_EQ(a[1].data, again[1].data);
    if (run == 0) first = a;
    else EXPECT_EQ(first[0].data, a[0].data);
  }
}

}  // namespace
}  // namespace dhr::server
