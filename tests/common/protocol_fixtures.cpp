#include "protocol_fixtures.hpp"

#include "codec/codec.hpp"
#include "metrics/visibility_synthetic.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <stdexcept>

namespace dhr::test {

View sample_view(double x) {
  View v;
  v.pose.position = {x, 1.6, -3.25};
  v.pose.orientation = glm::normalize(glm::dquat(0.9, 0.1, -0.3, 0.05));
  v.fov = Fov{-0.8f, 0.75f, 0.7f, -0.85f};
  return v;
}

std::vector<Datagram> sample_datagrams() {
  std::vector<Datagram> out;
  Hello hello;
  hello.client_nonce = 99;
  hello.eye_width = 1920;
  hello.eye_height = 1080;
  hello.guard_x = 32;
  hello.guard_y = 18;
  hello.light_count_wanted = 3;
  hello.scene_id = "living_room";
  out.push_back({0, 1, hello});
  Welcome welcome;
  welcome.client_nonce = 99;
  welcome.light_count = 17;
  welcome.mask_bits = MaskWidth::k32;
  welcome.buffer_width = 1984;
  welcome.buffer_height = 1116;
  welcome.guard_x = 32;
  welcome.guard_y = 18;
  out.push_back({kSampleToken, 2, welcome});
  PoseUpdate pose;
  pose.frame = 1234;
  pose.display_time_ns = 987654321;
  pose.scene_time_ns = 123456789;  // the scene clock starts at the session's start, the display clock earlier
  pose.views = {sample_view(-0.032), sample_view(0.032)};
  out.push_back({kSampleToken, 3, pose});
  // A real shard from the codec.
  const auto buffer = make_blob_visibility(160, 120, 3, 5);
  const auto shards = make_visibility_shards(buffer, 1234, Eye::kLeft, sample_view(0.0));
  if (shards.empty()) throw std::logic_error("sample_datagrams: the codec produced no shard");
  VisibilityShard shard = shards.front();
  shard.scene_time_ns = 123456789;  // traced at the pose's scene time
  out.push_back({kSampleToken, 4, shard});
  Heartbeat hb;
  hb.send_time_ns = 5;
  hb.echo_time_ns = 3;
  hb.echo_delay_ns = 1;
  out.push_back({kSampleToken, 5, hb});
  out.push_back({kSampleToken, 6, Bye{ByeReason::kTimeout}});
  NodeTransform moved;  // an app moved node 3 from 1.5 s on: 0.6 / 0.8 are a unit quaternion in f32 too
  moved.node = 3;
  moved.scene_time_ns = 1'500'000'000;
  moved.trs = Trs{glm::dvec3(0.25, -1.5, 2.0), glm::dquat(0.8, 0.0, 0.6, 0.0), glm::dvec3(1.0, 2.0, 0.5)};
  out.push_back({kSampleToken, 7, moved});
  return out;
}

}  // namespace dhr::test
