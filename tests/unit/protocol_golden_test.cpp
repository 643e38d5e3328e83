// Golden bytes: hand-written datagrams that lock the wire format (docs/protocol.md). A failure here
// means the format changed: bump kProtocolVersion and update docs/protocol.md with the bytes.
#include "protocol/protocol.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace dhr {
namespace {

using Bytes = std::vector<uint8_t>;

Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// Left view: position (1, 1.5, -2), identity orientation, FOV (-0.5, 0.5, 0.25, -0.25).
View left_view() {
  View v;
  v.pose.position = {1.0, 1.5, -2.0};
  v.pose.orientation = glm::dquat(1.0, 0.0, 0.0, 0.0);
  v.fov = Fov{-0.5f, 0.5f, 0.25f, -0.25f};
  return v;
}
const Bytes kLeftViewBytes = {
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF0, 0x3F,  // x = 1.0 (f64)
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF8, 0x3F,  // y = 1.5
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xC0,  // z = -2.0
    0x00, 0x00, 0x00, 0x00,                          // qx = 0 (f32)
    0x00, 0x00, 0x00, 0x00,                          // qy
    0x00, 0x00, 0x00, 0x00,                          // qz
    0x00, 0x00, 0x80, 0x3F,                          // qw = 1
    0x00, 0x00, 0x00, 0xBF,                          // angle_left = -0.5
    0x00, 0x00, 0x00, 0x3F,                          // angle_right = 0.5
    0x00, 0x00, 0x80, 0x3E,                          // angle_up = 0.25
    0x00, 0x00, 0x80, 0xBE,                          // angle_down = -0.25
};

// Right view: position (1.0625, 1.5, -2), orientation (x 0, y 0.6, z 0, w 0.8), same FOV.
View right_view() {
  View v = left_view();
  v.pose.position.x = 1.0625;
  v.pose.orientation = glm::dquat(0.8, 0.0, 0.6, 0.0);
  return v;
}
const Bytes kRightViewBytes = {
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF1, 0x3F,  // x = 1.0625
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF8, 0x3F,  // y = 1.5
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xC0,  // z = -2.0
    0x00, 0x00, 0x00, 0x00,                          // qx = 0
    0x9A, 0x99, 0x19, 0x3F,                          // qy = 0.6f
    0x00, 0x00, 0x00, 0x00,                          // qz = 0
    0xCD, 0xCC, 0x4C, 0x3F,                          // qw = 0.8f
    0x00, 0x00, 0x00, 0xBF, 0x00, 0x00, 0x00, 0x3F, 0x00, 0x00, 0x80, 0x3E, 0x00, 0x00, 0x80, 0xBE,
};

void expect_golden(const Datagram& d, const Bytes& expected) {
  EXPECT_EQ(encode_datagram(d), expected);
  EXPECT_EQ(encoded_size(d.message), expected.size());
  Datagram back;
  ASSERT_EQ(decode_datagram(expected, back), DecodeError::kNone);
  EXPECT_EQ(back.session_token, d.session_token);
  EXPECT_EQ(back.sequence, d.sequence);
  EXPECT_EQ(back.message.index(), d.message.index());
  EXPECT_EQ(encode_datagram(back), expected);  // decode -> encode is stable
}

void expect_views_near(const View& a, const View& b) {
  EXPECT_EQ(a.pose.position, b.pose.position);
  EXPECT_NEAR(a.pose.orientation.w, b.pose.orientation.w, 1e-6);
  EXPECT_NEAR(a.pose.orientation.x, b.pose.orientation.x, 1e-6);
  EXPECT_NEAR(a.pose.orientation.y, b.pose.orientation.y, 1e-6);
  EXPECT_NEAR(a.pose.orientation.z, b.pose.orientation.z, 1e-6);
  EXPECT_EQ(a.fov.angle_left, b.fov.angle_left);
  EXPECT_EQ(a.fov.angle_right, b.fov.angle_right);
  EXPECT_EQ(a.fov.angle_up, b.fov.angle_up);
  EXPECT_EQ(a.fov.angle_down, b.fov.angle_down);
}

TEST(ProtocolGolden, Hello) {
  Hello m;
  m.client_nonce = 0x1122334455667788ull;
  m.capabilities = kCapabilityLz4RowShards;
  m.eye_width = 1920;
  m.eye_height = 1080;
  m.guard_x = 32;
  m.guard_y = 18;
  m.light_count_wanted = 3;
  m.scene_id = "room";
  const Bytes expected = {
      'D', 'H', 'R', 'X',                              // magic
      0x07,                                            // version
      0x01,                                            // type Hello
      0x00, 0x00,                                      // reserved
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // token 0
      0x01, 0x02, 0x03, 0x04,                          // sequence 0x04030201
      0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11,  // client nonce
      0x01, 0x00, 0x00, 0x00,                          // capabilities
      0x80, 0x07, 0x38, 0x04,                          // eye 1920 x 1080
      0x20, 0x00, 0x12, 0x00,                          // guard 32, 18 per side
      0x03,                                            // lights wanted
      0x04, 'r', 'o', 'o', 'm',                        // scene id
  };
  expect_golden(Datagram{0, 0x04030201u, m}, expected);
  Datagram back;
  ASSERT_EQ(decode_datagram(expected, back), DecodeError::kNone);
  EXPECT_EQ(std::get<Hello>(back.message), m);
}

TEST(ProtocolGolden, Welcome) {
  Welcome m;
  m.client_nonce = 0x1122334455667788ull;
  m.capabilities = kCapabilityLz4RowShards;
  m.scene_hash = 0xCAFEBABEDEADBEEFull;
  m.light_count = 3;
  m.mask_bits = MaskWidth::k8;
  m.buffer_width = 1984;
  m.buffer_height = 1116;
  m.guard_x = 32;
  m.guard_y = 18;
  m.heartbeat_interval_ms = 1000;
  m.session_timeout_ms = 5000;
  const Bytes expected = {
      'D',  'H',  'R',  'X',  0x07, 0x02, 0x00, 0x00,  // magic, version, type Welcome, reserved
      0xEF, 0xCD, 0xAB, 0x89, 0x67, 0x45, 0x23, 0x01,  // token 0x0123456789ABCDEF
      0x07, 0x00, 0x00, 0x00,                          // sequence 7
      0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11,  // client nonce echo
      0x01, 0x00, 0x00, 0x00,                          // capabilities
      0xEF, 0xBE, 0xAD, 0xDE, 0xBE, 0xBA, 0xFE, 0xCA,  // scene hash
      0x03, 0x08, 0x00,                                // 3 lights, 8-bit masks, no soft light
      0xC0, 0x07, 0x5C, 0x04,                          // buffer 1984 x 1116
      0x20, 0x00, 0x12, 0x00,                          // guard 32, 18
      0xE8, 0x03,                                      // heartbeat 1000 ms
      0x88, 0x13, 0x00, 0x00,                          // timeout 5000 ms
  };
  expect_golden(Datagram{0x0123456789ABCDEFull, 7, m}, expected);
  Datagram back;
  ASSERT_EQ(decode_datagram(expected, back), DecodeError::kNone);
  EXPECT_EQ(std::get<Welcome>(back.message), m);
}

// Soft levels offered (capability bit 2) and granted: 3 lights of which 2 have a 3-bit level field, so
// 3 + 2 x 2 = 7 bits per mask in 8-bit masks.
TEST(ProtocolGolden, HelloOffersSoftLevels) {
  Hello m;
  m.client_nonce = 1;
  m.capabilities = kCapabilityLz4RowShards | kCapabilityCodecV2 | kCapabilitySoftLevels;
  m.eye_width = 320;
  m.eye_height = 240;
  const Bytes expected = {
      'D',  'H',  'R',  'X',  0x07, 0x01, 0x00, 0x00,  // magic, version 7, type Hello, flags
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // token 0
      0x00, 0x00, 0x00, 0x00,                          // sequence 0
      0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // client nonce 1
      0x07, 0x00, 0x00, 0x00,                          // capabilities: v1, v2, soft levels
      0x40, 0x01, 0xF0, 0x00,                          // eye 320 x 240
      0x00, 0x00, 0x00, 0x00,                          // no guard band
      0x00,                                            // lights wanted: all
      0x00,                                            // default scene
  };
  expect_golden(Datagram{0, 0, m}, expected);
  Datagram back;
  ASSERT_EQ(decode_datagram(expected, back), DecodeError::kNone);
  EXPECT_EQ(std::get<Hello>(back.message), m);
}

TEST(ProtocolGolden, WelcomeGrantsSoftLevels) {
  Welcome m;
  m.client_nonce = 1;
  m.capabilities = kCapabilityLz4RowShards | kCapabilitySoftLevels;
  m.scene_hash = 2;
  m.light_count = 3;
  m.mask_bits = MaskWidth::k8;
  m.soft_light_count = 2;
  m.buffer_width = 320;
  m.buffer_height = 240;
  m.heartbeat_interval_ms = 1000;
  m.session_timeout_ms = 5000;
  EXPECT_EQ(m.used_mask_bits(), 7u);
  const Bytes expected = {
      'D',  'H',  'R',  'X',  0x07, 0x02, 0x00, 0x00,  // magic, version 7, type Welcome, flags
      0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // token 1
      0x00, 0x00, 0x00, 0x00,                          // sequence 0
      0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // client nonce echo
      0x05, 0x00, 0x00, 0x00,                          // capabilities: v1, soft levels
      0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // scene hash
      0x03, 0x08, 0x02,                                // 3 lights, 8-bit masks, 2 with soft levels
      0x40, 0x01, 0xF0, 0x00,                          // buffer 320 x 240
      0x00, 0x00, 0x00, 0x00,                          // no guard band
      0xE8, 0x03,                                      // heartbeat 1000 ms
      0x88, 0x13, 0x00, 0x00,                          // timeout 5000 ms
  };
  expect_golden(Datagram{1, 0, m}, expected);
  Datagram back;
  ASSERT_EQ(decode_datagram(expected, back), DecodeError::kNone);
  EXPECT_EQ(std::get<Welcome>(back.message), m);
}

TEST(ProtocolGolden, PoseUpdate) {
  PoseUpdate m;
  m.frame = 42;
  m.display_time_ns = 1000000000;
  m.scene_time_ns = 250000000;
  m.views = {left_view(), right_view()};
  m.held_distance = {5, 0x0102};  // left holds frame 37, right frame 42 - 258: none (older than frame 0)
  const Bytes expected = cat({
      {'D', 'H', 'R', 'X', 0x07, 0x03, 0x00, 0x00},      // version 7, type PoseUpdate
      {0xEF, 0xCD, 0xAB, 0x89, 0x67, 0x45, 0x23, 0x01},  // token
      {0x08, 0x00, 0x00, 0x00},                          // sequence 8
      {0x2A, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00},  // frame 42
      {0x00, 0xCA, 0x9A, 0x3B, 0x00, 0x00, 0x00, 0x00},  // display time 1e9 ns
      {0x80, 0xB2, 0xE6, 0x0E, 0x00, 0x00, 0x00, 0x00},  // scene time 0.25 s
      kLeftViewBytes,
      kRightViewBytes,
      {0x05, 0x00, 0x02, 0x01},                          // held distances 5 and 258
  });
  ASSERT_EQ(expected.size(), 160u);
  expect_golden(Datagram{0x0123456789ABCDEFull, 8, m}, expected);
  Datagram back;
  ASSERT_EQ(decode_datagram(expected, back), DecodeError::kNone);
  const auto& p = std::get<PoseUpdate>(back.message);
  EXPECT_EQ(p.frame, 42u);
  EXPECT_EQ(p.display_time_ns, 1000000000);
  EXPECT_EQ(p.scene_time_ns, 250000000);
  expect_views_near(p.views[0], left_view());
  expect_views_near(p.views[1], right_view());
  EXPECT_EQ(p.held_frame(0), std::optional<uint64_t>(37));
  EXPECT_FALSE(p.held_frame(1).has_value());
  EXPECT_FALSE(p.held_frame(2).has_value());
}

TEST(ProtocolGolden, VisibilityShard) {
  VisibilityShard m;
  m.frame_number = 42;
  m.eye = Eye::kRight;
  m.mask_bits = MaskWidth::k8;
  m.shard_index = 2;
  m.shard_count = 5;
  m.buffer_width = 7;
  m.buffer_height = 5;
  m.first_pixel = 14;
  m.pixel_count = 7;
  m.scene_time_ns = 1250000000;
  m.view = left_view();
  const uint8_t payload[] = {0x00, 0x07, 0x00, 0x00, 0x00, 0x05};  // uniform chunk: 7 pixels of mask 0b101
  m.payload_size = sizeof(payload);
  std::copy(std::begin(payload), std::end(payload), m.payload.begin());
  const Bytes expected = cat({
      {'D', 'H', 'R', 'X', 0x07, 0x04, 0x00, 0x00},      // type VisibilityShard
      {0xEF, 0xCD, 0xAB, 0x89, 0x67, 0x45, 0x23, 0x01},  // token
      {0x09, 0x00, 0x00, 0x00},                          // sequence 9
      {0x2A, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00},  // frame 42
      {0x01, 0x08},                                      // right eye, 8-bit masks
      {0x02, 0x00, 0x05, 0x00},                          // shard 2 of 5
      {0x07, 0x00, 0x05, 0x00},                          // buffer 7 x 5
      {0x06, 0x00},                                      // payload size 6
      {0x0E, 0x00, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00},  // pixels [14, 21)
      {0x80, 0x7C, 0x81, 0x4A, 0x00, 0x00, 0x00, 0x00},  // traced at scene time 1.25 s
      kLeftViewBytes,
      {0x00, 0x07, 0x00, 0x00, 0x00, 0x05},  // payload
  });
  ASSERT_EQ(expected.size(), kShardFixedSize + 6);
  ASSERT_EQ(kShardFixedSize, 112u);
  ASSERT_EQ(kMaxShardPayload, 1152u);  // 1280 - 16 (the seal's tag) - 112
  expect_golden(Datagram{0x0123456789ABCDEFull, 9, m}, expected);
  Datagram back;
  ASSERT_EQ(decode_datagram(expected, back), DecodeError::kNone);
  const auto& s = std::get<VisibilityShard>(back.message);
  EXPECT_EQ(s.frame_number, 42u);
  EXPECT_EQ(s.eye, Eye::kRight);
  EXPECT_EQ(s.shard_index, 2);
  EXPECT_EQ(s.shard_count, 5);
  EXPECT_EQ(s.first_pixel, 14u);
  EXPECT_EQ(s.pixel_count, 7u);
  EXPECT_EQ(s.scene_time_ns, 1250000000);
  ASSERT_EQ(s.payload_size, 6);
  EXPECT_TRUE(std::equal(std::begin(payload), std::end(payload), s.payload.begin()));
  expect_views_near(s.view, left_view());
}

// A peer of version 4 (before the scene time) is recognised by bytes 0-4 and refused as another version, whatever
// its message: the server answers its Hello with Bye(version mismatch) (VisibilityServiceTest.*Version4*).
TEST(ProtocolGolden, Version4DatagramsAreRefusedAsAnotherVersion) {
  Hello hello;
  hello.eye_width = 320;
  hello.eye_height = 240;
  PoseUpdate pose;
  pose.frame = 1;
  pose.views = {left_view(), right_view()};
  for (const Message& m : {Message{hello}, Message{pose}}) {
    Bytes bytes = encode_datagram(Datagram{0, 0, m});
    ASSERT_GT(bytes.size(), 4u);
    bytes[4] = 4;
    DatagramHeader header;
    EXPECT_EQ(decode_header(bytes, header), DecodeError::kWrongVersion);
    EXPECT_EQ(header.version, 4);
    Datagram out;
    EXPECT_EQ(decode_datagram(bytes, out), DecodeError::kWrongVersion);
  }
}

TEST(ProtocolGolden, Heartbeat) {
  Heartbeat m;
  m.send_time_ns = 5000000000;
  m.echo_time_ns = 4000000000;
  m.echo_delay_ns = 250000;
  m.newest_frame = 41;
  m.datagrams_sent = 1;
  m.datagrams_received = 2;
  m.datagrams_rejected = 3;
  m.frames_done = 4;
  m.frames_dropped = 5;
  const Bytes expected = {
      'D',  'H',  'R',  'X',  0x07, 0x05, 0x00, 0x00,  // type Heartbeat
      0xEF, 0xCD, 0xAB, 0x89, 0x67, 0x45, 0x23, 0x01,  // token
      0x0A, 0x00, 0x00, 0x00,                          // sequence 10
      0x00, 0xF2, 0x05, 0x2A, 0x01, 0x00, 0x00, 0x00,  // send time 5e9
      0x00, 0x28, 0x6B, 0xEE, 0x00, 0x00, 0x00, 0x00,  // echo time 4e9
      0x90, 0xD0, 0x03, 0x00, 0x00, 0x00, 0x00, 0x00,  // echo delay 250000
      0x29, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // newest frame 41
      0x01, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00,  // counters
      0x04, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00,
  };
  expect_golden(Datagram{0x0123456789ABCDEFull, 10, m}, expected);
  Datagram back;
  ASSERT_EQ(decode_datagram(expected, back), DecodeError::kNone);
  EXPECT_EQ(std::get<Heartbeat>(back.message), m);
}

TEST(ProtocolGolden, Bye) {
  const Bytes expected = {
      'D',  'H',  'R',  'X',  0x07, 0x06, 0x00, 0x00,  // type Bye
      0xEF, 0xCD, 0xAB, 0x89, 0x67, 0x45, 0x23, 0x01,  // token
      0x0B, 0x00, 0x00, 0x00,                          // sequence 11
      0x03,                                            // reason: shutdown
  };
  expect_golden(Datagram{0x0123456789ABCDEFull, 11, Bye{ByeReason::kShutdown}}, expected);
  Datagram back;
  ASSERT_EQ(decode_datagram(expected, back), DecodeError::kNone);
  EXPECT_EQ(std::get<Bye>(back.message).reason, ByeReason::kShutdown);
}

}  // namespace
// Version 6: an application moved node 3 from scene time 1.5 s on (docs/motion.md, "App-moved nodes").
TEST(ProtocolGolden, NodeTransform) {
  NodeTransform m;
  m.node = 3;
  m.scene_time_ns = 1500000000;
  m.trs = Trs{glm::dvec3(0.25, -1.5, 2.0), glm::dquat(0.8, 0.0, 0.6, 0.0), glm::dvec3(1.0, 2.0, 0.5)};
  const Bytes expected = {
      'D',  'H',  'R',  'X',  0x07, 0x07, 0x00, 0x00,  // version 7, type NodeTransform
      0xEF, 0xCD, 0xAB, 0x89, 0x67, 0x45, 0x23, 0x01,  // token
      0x0C, 0x00, 0x00, 0x00,                          // sequence 12
      0x03, 0x00, 0x00, 0x00,                          // node 3
      0x00, 0x2F, 0x68, 0x59, 0x00, 0x00, 0x00, 0x00,  // scene time 1.5 s
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xD0, 0x3F,  // translation x = 0.25 (f64)
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF8, 0xBF,  // y = -1.5
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x40,  // z = 2.0
      0x00, 0x00, 0x00, 0x00,                          // rotation x = 0 (f32)
      0x9A, 0x99, 0x19, 0x3F,                          // y = 0.6f
      0x00, 0x00, 0x00, 0x00,                          // z = 0
      0xCD, 0xCC, 0x4C, 0x3F,                          // w = 0.8f
      0x00, 0x00, 0x80, 0x3F,                          // scale x = 1 (f32)
      0x00, 0x00, 0x00, 0x40,                          // y = 2
      0x00, 0x00, 0x00, 0x3F,                          // z = 0.5
  };
  ASSERT_EQ(expected.size(), 84u);
  expect_golden(Datagram{0x0123456789ABCDEFull, 12, m}, expected);
  Datagram back;
  ASSERT_EQ(decode_datagram(expected, back), DecodeError::kNone);
  const auto& t = std::get<NodeTransform>(back.message);
  EXPECT_EQ(t.node, 3u);
  EXPECT_EQ(t.scene_time_ns, 1500000000);
  EXPECT_EQ(t.trs.translation, m.trs.translation);
  EXPECT_EQ(t.trs.scale, m.trs.scale);
  EXPECT_NEAR(t.trs.rotation.y, 0.6, 1e-6);
  EXPECT_NEAR(t.trs.rotation.w, 0.8, 1e-6);
  EXPECT_NEAR(glm::length(t.trs.rotation), 1.0, 1e-12);  // renormalized
  // What the sender records is what the receiver holds.
  EXPECT_EQ(node_transform_as_decoded(m), std::optional<NodeTransform>(t));
}

}  // namespace dhr
