// App-moved nodes end to end (docs/motion.md, "App-moved nodes"): a node script (dhr-xrclient --node-script's
// format) played by the real client (VisibilityClient) moves the movable occluder of tests/common/
// test_movable_scene.hpp; the real server (VisibilityService, Embree) traces each frame with the transforms it
// received, and what arrives equals an exhaustive trace of scene_at with the client's own copy of them (the
// last frame is past the newest transform: extrapolated on both ends). In one process on SimulatedLinks with a
// VirtualClock: deterministic, no sockets.
#include "link/node_script.hpp"
#include "link/visibility_client.hpp"
#include "net/clock.hpp"
#include "net/simulated_link.hpp"
#include "scene/camera_bookmarks.hpp"
#include "scene/scene_at.hpp"
#include "scene/scene_hash.hpp"
#include "session/visibility_service.hpp"
#include "test_movable_scene.hpp"
#include "trace/embree/embree_tracer.hpp"

#include <gtest/gtest.h>

namespace dhr::client {
namespace {

constexpr int64_t kMs = net::kNsPerMs;
const net::PeerAddress kClientAddress = net::PeerAddress::ipv4({10, 0, 0, 1}, 5000);

// The occluder moves right at 0.1 s, then left and turned 45 degrees at 0.2 s; by 0.3 s both ends extrapolate.
constexpr const char* kScript = R"(# two transforms of the occluder
{"t": 0.1, "node": "Occluder", "translation": [1.5, 1, 0]}

{"t": 0.2, "node": 1, "translation": [0.5, 1, 0], "rotation": [0, 0.38268343, 0, 0.92387953]}
)";

TEST(NodeScriptEndToEnd, TheServerTracesTheNodesWhereTheClientPutThem) {
  const std::string text = test::movable_occluder_gltf();
  SceneLoadResult loaded = load_scene_from_memory(text.data(), text.size(), ".", "movable.gltf");
  ASSERT_TRUE(loaded) << loaded.error;
  const Scene scene = std::move(*loaded.scene);
  server::TracerOptions tracer_options;
  tracer_options.threads = 2;
  server::EmbreeTracer tracer(scene, tracer_options);

  net::VirtualClock clock(1'000 * kMs);
  net::SimulatedLink uplink({}, clock), downlink({}, clock);
  server::ServiceConfig service_config;
  service_config.scene_hash = scene_content_hash(scene);
  service_config.token_seed = 3;
  server::VisibilityService service(tracer, service_config, downlink, clock);
  VisibilityClientConfig client_config;
  client_config.format = TracedFormat{Extent{64, 48}, GuardBand{4, 3}};
  client_config.scene_hash = service_config.scene_hash;
  VisibilityClient client(client_config, uplink, clock);
  std::string error;
  std::optional<std::vector<NodeScriptStep>> steps = parse_node_script(kScript, scene, &error);
  ASSERT_TRUE(steps) << error;
  NodeScriptPlayer player(std::move(*steps), scene);

  const auto exchange = [&] {
    uplink.deliver_due([&](const net::SimulatedDelivery& d) { service.on_datagram(d.bytes, kClientAddress); });
    service.process_pending();
    downlink.deliver_due([&](const net::SimulatedDelivery& d) { client.on_datagram(d.bytes); });
  };
  client.tick();  // Hello
  exchange();
  ASSERT_TRUE(client.connected());

  const Pose head = look_at_pose(CameraBookmark{"floor", {0.0, 3.0, 4.0}, {0.0, 0.0, 0.0}}).value();
  const Fov fov = symmetric_fov(90.0, Extent{64, 48});
  VisibilityFrame newest, first;
  for (uint64_t frame = 1; frame <= 7; ++frame) {
    clock.advance_ns(50 * kMs);
    FramePose pose;
    pose.frame = frame;
    pose.display_time_ns = clock.now_ns();
    pose.scene_time_ns = static_cast<int64_t>(frame - 1) * 50 * kMs;  // 0 .. 0.3 s
    pose.views = {View{left_eye_pose(head), fov}, View{left_eye_pose(head, -kDefaultIpdMetres), fov}};
    player.play(pose.scene_time_ns, client);  // as NetworkVisibilitySource::send_pose does
    ASSERT_TRUE(client.send_pose(pose));
    exchange();
    VisibilityFrame got;
    ASSERT_TRUE(client.take_newest(Eye::kLeft, got)) << "frame " << frame;
    ASSERT_TRUE(got.complete);
    EXPECT_EQ(got.scene_time_ns, pose.scene_time_ns);
    if (frame == 1) first = got;
    newest = std::move(got);
  }
  EXPECT_EQ(player.sent(), 2u);
  EXPECT_EQ(client.stats().node_transforms_sent, 2u);
  const server::ServiceStats stats = service.stats();
  EXPECT_EQ(stats.node_transforms_applied, 2u);
  EXPECT_EQ(stats.node_transforms_dropped_late + stats.node_transforms_dropped_out_of_order +
                stats.node_transforms_dropped_unknown_node,
            0u);

  // The exhaustive reference: a fresh tracer on the scene at 0.3 s with the client's copy of the transforms.
  const double t = 0.3;
  EXPECT_NEAR(player.overrides().trs_at(test::kOccluderNode, t)->translation.x, -0.5, 1e-6);  // extrapolated
  const Camera camera = client.welcome()->format().camera(newest.view);
  const auto trace = [&](const Scene& s) {
    server::EmbreeTracer fresh(s, tracer_options);
    VisibilityBuffer out;
    server::TraceStats trace_stats;
    fresh.trace(camera, out, trace_stats);
    return out;
  };
  const VisibilityBuffer want = trace(scene_at(scene, t, &player.overrides()));
  EXPECT_EQ(newest.buffer.data, want.data);
  // The node did move: the same views with the occluder at rest (frame 1) differ.
  EXPECT_NE(first.buffer.data, newest.buffer.data);
  EXPECT_EQ(first.buffer.data, trace(scene_at(scene, 0.0)).data);
}

}  // namespace
}  // namespace dhr::client
