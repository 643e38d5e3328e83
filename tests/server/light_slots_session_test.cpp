// A session on a scene whose lights share light slots (more than 32; kCapabilityLightSlots): a Hello without the
// capability is refused with a reason, one asking for fewer fields too; with it the Welcome grants light slots with
// the tracer's field count, and the masks that arrive are the tracer's trace; with reuse on, a slowly drifting head's
// frames arrive as the exhaustive trace too, partly taken from the earlier ones.
#include "service_test_rig.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>

namespace dhr::server {
namespace {

using namespace test_rig;

SharedScene& many_lights_shared() {
  return kept_scene("many_lights_floor", [] {
    SceneLoadResult r;
    r.scene = test::many_lights_floor(8, 1.0f);  // 64 lights
    return r;
  });
}

// floor_views' head, `frame` millimetres to the right (the service does not trace an identical pose again).
std::array<View, 2> drifting_views(uint64_t frame) {
  const double x = 0.001 * static_cast<double>(frame);
  const Pose head = look_at_pose(CameraBookmark{"floor", {x, 3.0, 4.0}, {x, 0.0, 0.0}}).value();
  const Fov fov = symmetric_fov(90.0, Extent{kEyeW, kEyeH});
  return {View{left_eye_pose(head), fov}, View{left_eye_pose(head, -kDefaultIpdMetres), fov}};
}

class LightSlotsSessionTest : public VisibilityServiceTest {
 protected:
  void SetUp() override { serve("many_lights_floor", many_lights_shared(), 5); }

  std::vector<Datagram> hello(uint32_t capabilities, uint8_t lights = 0) {
    Hello h = make_hello(21, lights);
    h.capabilities = capabilities;
    send(Datagram{0, 0, h}, peer(1));
    return drain()[peer(1)];
  }
};

TEST_F(LightSlotsSessionTest, AClientWithoutLightSlotsIsRefused) {
  ASSERT_NE(many_lights_shared().tracer->light_slots(), nullptr);
  for (const std::vector<Datagram>& sent : {hello(kCapabilityLz4RowShards | kCapabilityCodecV2),
                                            hello(kCapabilityLz4RowShards | kCapabilityLightSlots, 3)}) {
    ASSERT_EQ(sent.size(), 1u);
    ASSERT_TRUE(std::holds_alternative<Bye>(sent[0].message));
    EXPECT_EQ(std::get<Bye>(sent[0].message).reason, ByeReason::kBadHello);
  }
  EXPECT_EQ(service_->stats().hellos_rejected, 2u);
}

TEST_F(LightSlotsSessionTest, GrantedLightSlotsArriveAsTraced) {
  const LightSlots& slots = *many_lights_shared().tracer->light_slots();
  for (const uint32_t codec : {0u, kCapabilityCodecV2}) {
    make_service();
    const std::vector<Datagram> sent = hello(kCapabilityLz4RowShards | codec | kCapabilityLightSlots);
    ASSERT_EQ(sent.size(), 1u);
    const Welcome w = std::get<Welcome>(sent[0].message);
    EXPECT_TRUE(w.capabilities & kCapabilityLightSlots);
    EXPECT_EQ(w.light_count, slots.slot_count());
    EXPECT_EQ(w.soft_light_count, 0u);
    const std::array<View, 2> views = send_pose(sent[0].session_token, peer(1), 1, floor_views());
    service_->process_pending();
    const std::array<VisibilityBuffer, 2> got = reassemble(w, shards_of(drain()[peer(1)]), 1);
    for (size_t e = 0; e < 2; ++e) {
      VisibilityBuffer want;
      TraceStats stats;
      many_lights_shared().tracer->trace(TracedFormat{Extent{kEyeW, kEyeH}, GuardBand{kGuardX, kGuardY}}.camera(views[e]),
                                         want, stats);
      EXPECT_EQ(got[e], want) << "eye " << e;
      size_t shadowed = 0;  // a hit pixel with some field 0: a light whose ray was occluded
      for (size_t p = 0; p < want.pixel_count(); ++p) shadowed += want.mask_at(p) != 0 && want.mask_at(p) != want.light_bits();
      EXPECT_GT(shadowed, 0u) << "eye " << e;
    }
  }
}

TEST_F(LightSlotsSessionTest, ReuseTakesFromEarlierFramesAndShowsTheExhaustiveBits) {
  config_.reuse = true;
  make_service();
  // Codec v1: each frame decodes on its own (v2 would code frames 2 and 3 against frames this rig does not keep).
  const std::vector<Datagram> sent = hello(kCapabilityLz4RowShards | kCapabilityLightSlots);
  ASSERT_EQ(sent.size(), 1u);
  const Welcome w = std::get<Welcome>(sent[0].message);
  for (uint64_t f = 1; f <= 3; ++f) {
    const std::array<View, 2> views = send_pose(sent[0].session_token, peer(1), f, drifting_views(f));
    service_->process_pending();
    const std::array<VisibilityBuffer, 2> got = reassemble(w, shards_of(drain()[peer(1)]), f);
    for (size_t e = 0; e < 2; ++e) {
      VisibilityBuffer want;
      TraceStats stats;
      many_lights_shared().tracer->trace(TracedFormat{Extent{kEyeW, kEyeH}, GuardBand{kGuardX, kGuardY}}.camera(views[e]),
                                         want, stats);
      EXPECT_EQ(got[e], want) << "frame " << f << " eye " << e;
    }
  }
  EXPECT_GT(service_->stats().reused_pixels + service_->stats().reused_pairs, 0u);
}

}  // namespace
}  // namespace dhr::server
