// The server's session layer (VisibilityService, real Embree tracer, simulated link, virtual clock):
//  - skipping the re-trace of a bit-identical pose changes nothing the client sees: after every pose the
//    newest reassembled buffer of each eye has the same bits with the skip on and off;
//  - PoseUpdates with NaN / Inf / zero quaternions / huge translations are rejected, counted per decode
//    error, and never traced.
#include "scene/camera_bookmarks.hpp"
#include "codec/reassembly.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "net/simulated_link.hpp"
#include "session/visibility_service.hpp"
#include "stress_support.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <memory>

namespace dhr::stress {
namespace {

constexpr uint16_t kEyeW = 48, kEyeH = 36, kGuardX = 4, kGuardY = 3;

std::array<View, 2> bookmark_views(size_t index) {
  std::string error;
  const auto bookmarks = load_camera_bookmarks(
      camera_bookmarks_path(test::source_path(kDefaultScenePath)), &error);
  EXPECT_TRUE(bookmarks) << error;
  const CameraBookmark b = bookmarks->at(index % bookmarks->size());
  const Pose head = look_at_pose(b).value();
  const Fov fov = symmetric_fov(90.0, Extent{kEyeW, kEyeH});
  return {View{left_eye_pose(head), fov}, View{left_eye_pose(head, -kDefaultIpdMetres), fov}};
}

// One service with its own link, clock and client-side reassembler.
struct Rig {
  net::VirtualClock clock{1'000'000'000};
  net::SimulatedLink link{net::ImpairmentParams{}, clock};
  std::unique_ptr<server::VisibilityService> service;
  std::unique_ptr<VisibilityReassembler> reassembler;
  uint64_t token = 0;
  net::PeerAddress peer = net::PeerAddress::ipv4({10, 0, 0, 1}, 5000);

  Rig(server::VisibilityTracer& tracer, bool skip_identical) {
    server::ServiceConfig config;
    config.scene_id = "default_room";
    config.token_seed = 7;
    config.skip_identical_pose = skip_identical;
    service = std::make_unique<server::VisibilityService>(tracer, config, link, clock);
    Hello hello;
    hello.client_nonce = 1;
    hello.eye_width = kEyeW;
    hello.eye_height = kEyeH;
    hello.guard_x = kGuardX;
    hello.guard_y = kGuardY;
    service->on_datagram(encode_datagram(Datagram{0, 0, hello}), peer);
    link.deliver_due([&](const net::SimulatedDelivery& d) {
      Datagram dg;
      ASSERT_EQ(decode_datagram(d.bytes, dg), DecodeError::kNone);
      const auto* w = std::get_if<Welcome>(&dg.message);
      ASSERT_NE(w, nullptr);
      token = dg.session_token;
      ReassemblerConfig rc;
      rc.width = w->buffer_width;
      rc.height = w->buffer_height;
      rc.light_count = w->used_mask_bits();
      reassembler = std::make_unique<VisibilityReassembler>(rc);
    });
  }

  // Sends the pose, lets the server trace, delivers every shard to the reassembler.
  void step(uint64_t frame, const std::array<View, 2>& views) {
    PoseUpdate p;
    p.frame = frame;
    p.display_time_ns = int64_t(frame) * 11'000'000;
    p.views = views;
    service->on_datagram(encode_datagram(Datagram{token, uint32_t(frame), p}), peer);
    clock.advance_ns(11'000'000);
    service->process_pending();
    link.deliver_due([&](const net::SimulatedDelivery& d) {
      Datagram dg;
      if (decode_datagram(d.bytes, dg) != DecodeError::kNone) return;
      if (const auto* s = std::get_if<VisibilityShard>(&dg.message)) reassembler->insert(*s);
    });
  }
};

TEST(SkipEquivalence, IdenticalPoseSkipChangesNoBitTheClientSees) {
  const Scene scene = load_scene_or_fail(test::source_path(kDefaultScenePath));
  server::EmbreeTracer tracer(scene, embree_options());
  Rig skipping(tracer, true), exhaustive(tracer, false);
  ASSERT_TRUE(skipping.reassembler && exhaustive.reassembler);
  // A still head, a move, still again, back to the first pose.
  const std::vector<size_t> sequence = {0, 0, 0, 1, 1, 1, 0, 0};
  uint64_t differing = 0;
  for (size_t n = 0; n < sequence.size(); ++n) {
    const auto views = bookmark_views(sequence[n]);
    skipping.step(n + 1, views);
    exhaustive.step(n + 1, views);
    for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
      const ReassembledFrame* a = skipping.reassembler->latest_complete(eye);
      const ReassembledFrame* b = exhaustive.reassembler->latest_complete(eye);
      ASSERT_TRUE(a != nullptr && b != nullptr) << "frame " << n + 1;
      differing += differing_bits(a->visibility.buffer, b->visibility.buffer);
    }
  }
  const server::ServiceStats sa = skipping.service->stats(), sb = exhaustive.service->stats();
  report("skip_identical_pose", "differing_bits", double(differing), 0.0);
  std::printf("[stress] skip_identical_pose: frames traced %llu vs %llu, bytes sent %llu vs %llu\n",
              static_cast<unsigned long long>(sa.frames_traced), static_cast<unsigned long long>(sb.frames_traced),
              static_cast<unsigned long long>(sa.bytes_sent), static_cast<unsigned long long>(sb.bytes_sent));
  EXPECT_EQ(differing, 0u);
  EXPECT_EQ(sa.poses_skipped_identical, 5u);  // frames 2, 3, 5, 6, 8
  EXPECT_EQ(sb.poses_skipped_identical, 0u);
  EXPECT_EQ(sb.frames_traced, sequence.size());
  EXPECT_EQ(sa.frames_traced + sa.poses_skipped_identical, sb.frames_traced);
}

TEST(StressPoses, BadPosesInASessionAreCountedAndNeverTraced) {
  const Scene scene = load_scene_or_fail(test::source_path(kDefaultScenePath));
  server::EmbreeTracer tracer(scene, embree_options());
  Rig rig(tracer, true);
  ASSERT_TRUE(rig.reassembler);
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN(), kInf = std::numeric_limits<double>::infinity();
  const std::vector<std::pair<glm::dvec3, glm::dquat>> bad = {
      {{kNaN, 1.6, 0}, {1, 0, 0, 0}}, {{0, kInf, 0}, {1, 0, 0, 0}}, {{0, 1.6, 0}, {kNaN, 0, 0, 0}},
      {{0, 1.6, 0}, {0, 0, 0, 0}},    {{3e6, 1.6, 0}, {1, 0, 0, 0}}, {{0, 1e300, 0}, {1, 0, 0, 0}}};
  uint64_t frame = 1;
  for (const auto& [position, orientation] : bad) {
    auto views = bookmark_views(0);
    views[frame % 2].pose.position = position;
    views[frame % 2].pose.orientation = orientation;
    rig.step(frame++, views);
  }
  server::ServiceStats s = rig.service->stats();
  report("bad_pose_session", "bad_poses_traced", double(s.frames_traced), 0.0);
  EXPECT_EQ(s.datagrams_rejected, bad.size());
  EXPECT_EQ(s.decode_errors.total_errors(), bad.size());
  EXPECT_EQ(s.decode_errors[DecodeError::kNonFinite] + s.decode_errors[DecodeError::kBadPose], bad.size());
  EXPECT_EQ(s.frames_traced, 0u);
  EXPECT_EQ(rig.reassembler->latest_complete(Eye::kLeft), nullptr);
  // The session is unharmed: the next good pose is traced.
  rig.step(frame, bookmark_views(1));
  s = rig.service->stats();
  EXPECT_EQ(s.frames_traced, 1u);
  EXPECT_NE(rig.reassembler->latest_complete(Eye::kLeft), nullptr);
}

}  // namespace
}  // namespace dhr::stress
