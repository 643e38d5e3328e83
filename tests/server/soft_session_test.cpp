// Soft levels in a session (VisibilityService on assets/scenes/default_room_area.gltf): the capability is granted
// exactly when the client offers it and the session's lights include one with an extent; the masks that arrive
// are then the tracer's trace_layout of the soft layout (both codecs), and otherwise exactly the hard layout.
#include "service_test_rig.hpp"
#include "session/service_stats_json.hpp"

#include <gtest/gtest.h>

namespace dhr::server {
namespace {

using namespace test_rig;

constexpr const char* kAreaScene = "assets/scenes/default_room_area.gltf";

SharedScene& area_shared() { return shared_scene(kAreaScene); }

std::array<View, 2> area_views(size_t index) {
  std::string error;
  const auto bookmarks = load_camera_bookmarks(camera_bookmarks_path(test::source_path(kAreaScene)), &error).value();
  const CameraBookmark& b = bookmarks.at(index % bookmarks.size());
  const Pose head = look_at_pose(b).value();
  const Fov fov = symmetric_fov(90.0, Extent{kEyeW, kEyeH});
  return {View{left_eye_pose(head), fov}, View{left_eye_pose(head, -kDefaultIpdMetres), fov}};
}

class SoftSessionTest : public VisibilityServiceTest {
 protected:
  void SetUp() override { serve("default_room_area", area_shared(), 7); }

  // Hello with `capabilities` -> Welcome; a pose from bookmark `view` traced and reassembled.
  Welcome connect_and_trace(uint32_t capabilities, uint8_t lights, size_t view, std::array<VisibilityBuffer, 2>& out,
                            std::array<View, 2>& out_views) {
    Hello h = make_hello(11, lights);
    h.capabilities = capabilities;
    const net::PeerAddress from = peer(1);
    send(Datagram{0, 0, h}, from);
    auto sent = drain();
    EXPECT_EQ(sent[from].size(), 1u);
    const Welcome w = std::get<Welcome>(sent[from].at(0).message);
    const uint64_t token = sent[from][0].session_token;
    out_views = send_pose(token, from, 1, area_views(view));
    service_->process_pending();
    sent = drain();
    out = reassemble(w, shards_of(sent[from]), 1);
    return w;
  }

  static VisibilityBuffer trace_in(const View& view, const VisibilityLayout& layout) {
    VisibilityBuffer out;
    TraceStats stats;
    area_shared().tracer->trace_layout(TracedFormat{Extent{kEyeW, kEyeH}, GuardBand{kGuardX, kGuardY}}.camera(view),
                                       layout, out, stats);
    return out;
  }

  static VisibilityLayout soft_layout(uint32_t lights) {
    return layout_for_lights(area_shared().tracer->light_extents(), lights);
  }
};

uint32_t soft_count(const VisibilityLayout& layout) {
  uint32_t n = 0;
  for (uint32_t i = 0; i < layout.light_count; ++i) n += layout.is_soft(i) ? 1u : 0u;
  return n;
}

TEST_F(SoftSessionTest, OfferedSoftLevelsAreGrantedAndArriveAsTraced) {
  for (const uint32_t codec : {0u, kCapabilityCodecV2}) {
    make_service();
    std::array<VisibilityBuffer, 2> got;
    std::array<View, 2> views;
    const Welcome w = connect_and_trace(kCapabilityLz4RowShards | codec | kCapabilitySoftLevels, 0, 0, got, views);
    const VisibilityLayout layout = soft_layout(area_shared().tracer->light_count());
    ASSERT_TRUE(layout.any_soft());
    EXPECT_TRUE(w.capabilities & kCapabilitySoftLevels);
    EXPECT_EQ(w.capabilities & kCapabilityCodecV2, codec);
    EXPECT_EQ(w.light_count, layout.light_count);
    EXPECT_EQ(w.soft_light_count, soft_count(layout));
    EXPECT_EQ(w.used_mask_bits(), layout.total_bits());
    EXPECT_EQ(w.mask_bits, layout.mask_width());
    for (int e = 0; e < 2; ++e) EXPECT_TRUE(got[e] == trace_in(views[e], layout)) << "eye " << e << " codec " << codec;
    const ServiceStats st = service_->stats();
    EXPECT_EQ(st.sessions_soft, 1u);
    EXPECT_GT(st.soft_pairs, 0u);
    EXPECT_GT(st.soft_shadow_rays, st.soft_contributing_pairs);  // at least the first 4 samples each
    EXPECT_TRUE(to_json(st).contains("soft_rays_per_pair"));
    EXPECT_TRUE(to_json(st).contains("soft_refined_share"));
  }
}

TEST_F(SoftSessionTest, WithoutTheCapabilityTheLayoutIsExactlyHard) {
  std::array<VisibilityBuffer, 2> got;
  std::array<View, 2> views;
  const Welcome w = connect_and_trace(kCapabilityLz4RowShards | kCapabilityCodecV2, 0, 1, got, views);
  const uint32_t n = area_shared().tracer->light_count();
  EXPECT_FALSE(w.capabilities & kCapabilitySoftLevels);
  EXPECT_EQ(w.soft_light_count, 0u);
  EXPECT_EQ(w.used_mask_bits(), n);
  EXPECT_EQ(w.mask_bits, mask_width_for_light_count(n));
  for (int e = 0; e < 2; ++e) {
    VisibilityBuffer hard;
    TraceStats stats;
    area_shared().tracer->trace_lights(
        TracedFormat{Extent{kEyeW, kEyeH}, GuardBand{kGuardX, kGuardY}}.camera(views[e]), n, hard, stats);
    EXPECT_TRUE(got[e] == hard) << "eye " << e;
  }
  EXPECT_EQ(service_->stats().sessions_soft, 0u);
  EXPECT_EQ(service_->stats().soft_pairs, 0u);
}

TEST_F(SoftSessionTest, ServerWithSoftLevelsOffGrantsNone) {
  config_.soft_levels = false;
  make_service();
  std::array<VisibilityBuffer, 2> got;
  std::array<View, 2> views;
  const Welcome w = connect_and_trace(kCapabilityLz4RowShards | kCapabilitySoftLevels, 0, 0, got, views);
  EXPECT_FALSE(w.capabilities & kCapabilitySoftLevels);
  EXPECT_EQ(w.soft_light_count, 0u);
  for (int e = 0; e < 2; ++e)
    EXPECT_TRUE(got[e] == trace_in(views[e], VisibilityLayout::hard(area_shared().tracer->light_count())));
}

// A client asking for fewer lights gets soft levels only when one of those lights has an extent.
TEST_F(SoftSessionTest, GrantFollowsTheRequestedLights) {
  const uint32_t n = area_shared().tracer->light_count();
  for (uint32_t k = 1; k <= n; ++k) {
    make_service();
    Hello h = make_hello(20 + k, static_cast<uint8_t>(k));
    h.capabilities = kCapabilityLz4RowShards | kCapabilitySoftLevels;
    const net::PeerAddress from = peer(2);
    send(Datagram{0, 0, h}, from);
    auto sent = drain();
    ASSERT_EQ(sent[from].size(), 1u);
    const Welcome w = std::get<Welcome>(sent[from][0].message);
    const VisibilityLayout layout = soft_layout(k);
    EXPECT_EQ(w.light_count, k);
    EXPECT_EQ(w.soft_light_count, soft_count(layout)) << k;
    EXPECT_EQ((w.capabilities & kCapabilitySoftLevels) != 0, layout.any_soft()) << k;
    EXPECT_EQ(w.used_mask_bits(), layout.any_soft() ? layout.total_bits() : k);
  }
}

// The default room has no light with an extent: offering soft levels changes nothing.
TEST_F(VisibilityServiceTest, SoftLevelsOfferedForAHardSceneGetTheHardLayout) {
  Hello h = make_hello(5);
  h.capabilities = kCapabilityLz4RowShards | kCapabilitySoftLevels;
  const net::PeerAddress from = peer(3);
  send(Datagram{0, 0, h}, from);
  auto sent = drain();
  ASSERT_EQ(sent[from].size(), 1u);
  const Welcome w = std::get<Welcome>(sent[from][0].message);
  EXPECT_FALSE(w.capabilities & kCapabilitySoftLevels);
  EXPECT_EQ(w.soft_light_count, 0u);
  EXPECT_EQ(w.used_mask_bits(), w.light_count);
}

}  // namespace
}  // namespace dhr::server
