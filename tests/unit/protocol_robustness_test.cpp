// Every decoder rejects every truncation, bad field and random corruption with an error code, never a
// crash (run these under -DDHR_SANITIZE=address,undefined too).
#include "codec/codec.hpp"
#include "protocol/protocol.hpp"
#include "protocol_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace dhr {
namespace {

using Bytes = std::vector<uint8_t>;
using test::sample_datagrams;
constexpr uint64_t kToken = test::kSampleToken;

TEST(ProtocolRobustness, RoundTripsEveryMessage) {
  for (const Datagram& d : sample_datagrams()) {
    const Bytes bytes = encode_datagram(d);
    ASSERT_FALSE(bytes.empty());
    ASSERT_LE(bytes.size(), kMaxDatagramSize);
    Datagram back;
    ASSERT_EQ(decode_datagram(bytes, back), DecodeError::kNone) << to_string(message_type(d.message));
    EXPECT_EQ(back.session_token, d.session_token);
    EXPECT_EQ(back.sequence, d.sequence);
    EXPECT_EQ(message_type(back.message), message_type(d.message));
    EXPECT_EQ(encode_datagram(back), bytes);
  }
}

TEST(ProtocolRobustness, EveryTruncationIsRejected) {
  for (const Datagram& d : sample_datagrams()) {
    const Bytes bytes = encode_datagram(d);
    for (size_t n = 0; n < bytes.size(); ++n) {
      Datagram out;
      const Bytes prefix(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
      EXPECT_EQ(decode_datagram(prefix.data(), prefix.size(), out), DecodeError::kTruncated)
          << to_string(message_type(d.message)) << " prefix " << n;
    }
  }
}

TEST(ProtocolRobustness, TrailingAndOversizeAreRejected) {
  for (const Datagram& d : sample_datagrams()) {
    Bytes bytes = encode_datagram(d);
    bytes.push_back(0);
    Datagram out;
    // A full shard is exactly kMaxDatagramSize: one more byte makes it oversize instead.
    EXPECT_EQ(decode_datagram(bytes, out),
              bytes.size() > kMaxDatagramSize ? DecodeError::kOversize : DecodeError::kTrailingBytes);
  }
  Bytes huge = encode_datagram(sample_datagrams()[0]);
  huge.resize(kMaxDatagramSize + 1);
  Datagram out;
  EXPECT_EQ(decode_datagram(huge, out), DecodeError::kOversize);
}

TEST(ProtocolRobustness, HeaderFieldsAreChecked) {
  const Bytes good = encode_datagram(sample_datagrams()[2]);
  Datagram out;
  DatagramHeader header;
  ASSERT_EQ(decode_header(good, header), DecodeError::kNone);
  EXPECT_EQ(header.type, MessageType::kPoseUpdate);

  Bytes b = good;
  b[0] = 'X';
  EXPECT_EQ(decode_datagram(b, out), DecodeError::kBadMagic);
  b = good;
  b[4] = 2;
  EXPECT_EQ(decode_header(b, header), DecodeError::kWrongVersion);
  EXPECT_EQ(header.version, 2);  // reported so the receiver can log the peer's version
  b = good;
  b[5] = 0;
  EXPECT_EQ(decode_datagram(b, out), DecodeError::kUnknownType);
  b[5] = 8;  // one past NodeTransform
  EXPECT_EQ(decode_datagram(b, out), DecodeError::kUnknownType);
  b = good;
  b[7] = 1;
  EXPECT_EQ(decode_datagram(b, out), DecodeError::kBadReserved);
  b = good;
  for (int i = 8; i < 16; ++i) b[i] = 0;  // PoseUpdate without a session token
  EXPECT_EQ(decode_datagram(b, out), DecodeError::kBadToken);
  Bytes hello = encode_datagram(sample_datagrams()[0]);
  hello[8] = 1;  // Hello with a token
  EXPECT_EQ(decode_datagram(hello, out), DecodeError::kBadToken);
}

TEST(ProtocolRobustness, PoseValuesAreValidated) {
  PoseUpdate base = std::get<PoseUpdate>(sample_datagrams()[2].message);
  auto decode_pose = [](const PoseUpdate& p) {
    Datagram out;
    return decode_datagram(encode_datagram(Datagram{kToken, 0, p}), out);
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  PoseUpdate p = base;
  p.views[1].pose.position.y = nan;
  EXPECT_EQ(decode_pose(p), DecodeError::kNonFinite);
  p = base;
  p.views[0].pose.orientation.x = inf;
  EXPECT_EQ(decode_pose(p), DecodeError::kNonFinite);
  p = base;
  p.views[0].fov.angle_up = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(decode_pose(p), DecodeError::kNonFinite);
  p = base;
  p.views[0].pose.orientation = glm::dquat(0.0, 0.0, 0.0, 0.0);
  EXPECT_EQ(decode_pose(p), DecodeError::kBadPose);
  p = base;
  p.views[0].pose.orientation = glm::dquat(0.5, 0.0, 0.0, 0.0);  // |q| = 0.5: corrupt, not rounding
  EXPECT_EQ(decode_pose(p), DecodeError::kBadPose);
  p = base;
  p.views[1].pose.position.x = 2.0 * kMaxPositionMetres;
  EXPECT_EQ(decode_pose(p), DecodeError::kBadPose);
  p = base;
  p.views[1].fov = Fov{0.5f, -0.5f, 0.5f, -0.5f};  // left > right
  EXPECT_EQ(decode_pose(p), DecodeError::kBadFov);
  p = base;
  p.views[1].fov.angle_right = 1.6f;  // beyond 90 degrees
  EXPECT_EQ(decode_pose(p), DecodeError::kBadFov);
  p = base;
  p.display_time_ns = -1;
  EXPECT_EQ(decode_pose(p), DecodeError::kBadValue);
  p = base;
  p.scene_time_ns = -1;  // the scene clock starts at 0 (the session's start)
  EXPECT_EQ(decode_pose(p), DecodeError::kBadValue);
  p.scene_time_ns = INT64_MIN;
  EXPECT_EQ(decode_pose(p), DecodeError::kBadValue);

  // A slightly denormalized quaternion (float rounding) is accepted and renormalized.
  p = base;
  p.views[0].pose.orientation = glm::dquat(1.0002, 0.0, 0.0, 0.0);
  Datagram out;
  ASSERT_EQ(decode_datagram(encode_datagram(Datagram{kToken, 0, p}), out), DecodeError::kNone);
  const glm::dquat q = std::get<PoseUpdate>(out.message).views[0].pose.orientation;
  EXPECT_NEAR(glm::length(q), 1.0, 1e-12);

  // Large world coordinates survive exactly (f64 on the wire).
  p = base;
  p.views[0].pose.position = {123456.789012345, -0.000001, 987654.3210987};
  ASSERT_EQ(decode_datagram(encode_datagram(Datagram{kToken, 0, p}), out), DecodeError::kNone);
  EXPECT_EQ(std::get<PoseUpdate>(out.message).views[0].pose.position, p.views[0].pose.position);
}

// A view computed in f64 (a predicted one) is not what the receiver decodes; view_as_decoded() is, bit for
// bit, for PoseUpdate and VisibilityShard alike, and refuses what decoding refuses.
TEST(ProtocolRobustness, ViewAsDecodedIsWhatTheReceiverHolds) {
  View view;
  view.pose.position = {0.3067, 1.6380, 1.3468};
  view.pose.orientation = glm::normalize(glm::dquat(0.9706914, -0.2318, 0.0613, 0.0189));  // not f32 values
  view.fov = Fov{-0.8f, 0.75f, 0.7f, -0.72f};
  const std::optional<View> decoded = view_as_decoded(view);
  ASSERT_TRUE(decoded.has_value());
  EXPECT_NE(decoded->pose.orientation, view.pose.orientation);  // the wire's f32 changed it
  PoseUpdate pose = std::get<PoseUpdate>(sample_datagrams()[2].message);
  pose.views = {view, view};
  Datagram out;
  ASSERT_EQ(decode_datagram(encode_datagram(Datagram{kToken, 0, pose}), out), DecodeError::kNone);
  for (const View& v : std::get<PoseUpdate>(out.message).views) {
    EXPECT_EQ(v.pose.position, decoded->pose.position);
    EXPECT_EQ(v.pose.orientation, decoded->pose.orientation);
    EXPECT_EQ(v.fov.angle_left, decoded->fov.angle_left);
    EXPECT_EQ(v.fov.angle_down, decoded->fov.angle_down);
  }
  for (const Datagram& d : sample_datagrams()) {
    if (!std::holds_alternative<VisibilityShard>(d.message)) continue;
    Datagram shard = d;
    std::get<VisibilityShard>(shard.message).view = view;
    ASSERT_EQ(decode_datagram(encode_datagram(shard), out), DecodeError::kNone);
    EXPECT_EQ(std::get<VisibilityShard>(out.message).view.pose.orientation, decoded->pose.orientation);
  }
  View bad = view;
  bad.pose.position.x = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(view_as_decoded(bad).has_value());
  bad = view;
  bad.fov.angle_right = 1.6f;
  EXPECT_FALSE(view_as_decoded(bad).has_value());
}

TEST(ProtocolRobustness, OtherFieldRangesAreValidated) {
  const auto samples = sample_datagrams();
  Datagram out;
  {
    Hello h = std::get<Hello>(samples[0].message);
    h.light_count_wanted = 33;
    EXPECT_EQ(decode_datagram(encode_datagram({0, 0, h}), out), DecodeError::kBadValue);
    h = std::get<Hello>(samples[0].message);
    h.eye_width = 0;
    EXPECT_EQ(decode_datagram(encode_datagram({0, 0, h}), out), DecodeError::kBadValue);
    h = std::get<Hello>(samples[0].message);
    h.eye_width = 4000;
    h.guard_x = 100;  // traced width 4200 > kMaxBufferDimension
    EXPECT_EQ(decode_datagram(encode_datagram({0, 0, h}), out), DecodeError::kBadValue);
    h = std::get<Hello>(samples[0].message);
    h.scene_id = std::string("bad\nname");
    EXPECT_EQ(decode_datagram(encode_datagram({0, 0, h}), out), DecodeError::kBadString);
    h.scene_id = std::string(kMaxSceneIdLength + 1, 'a');
    EXPECT_TRUE(encode_datagram({0, 0, h}).empty());  // not representable
    h.scene_id = std::string(kMaxSceneIdLength, 'a');
    EXPECT_EQ(decode_datagram(encode_datagram({0, 0, h}), out), DecodeError::kNone);
  }
  {
    Welcome w = std::get<Welcome>(samples[1].message);
    w.mask_bits = MaskWidth::k16;  // 17 lights need 32 bits
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kBadValue);
    w = std::get<Welcome>(samples[1].message);
    w.light_count = 40;
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kBadValue);
    w = std::get<Welcome>(samples[1].message);
    w.guard_x = 992;  // 2 * guard >= width
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kBadValue);
    w = std::get<Welcome>(samples[1].message);
    w.heartbeat_interval_ms = 0;
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kBadValue);
    // Soft levels: the capability and a soft light count come together, and every field fits 32 bits.
    w = std::get<Welcome>(samples[1].message);  // 17 lights, 32-bit masks
    w.soft_light_count = 2;                     // 21 bits, but the capability is not granted
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kBadValue);
    w.capabilities |= kCapabilitySoftLevels;
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kNone);
    w.soft_light_count = 0;  // granted, but no light has levels
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kBadValue);
    w.soft_light_count = 8;  // 17 + 16 = 33 bits
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kBadValue);
    w.light_count = 3;
    w.soft_light_count = 4;  // more soft lights than lights
    w.mask_bits = MaskWidth::k16;
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kBadValue);
    w.soft_light_count = 3;  // 3 + 6 = 9 bits: 16-bit masks, not 8
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kNone);
    w.mask_bits = MaskWidth::k8;
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, w}), out), DecodeError::kBadValue);
  }
  {
    const VisibilityShard base = std::get<VisibilityShard>(samples[3].message);
    auto check = [&](auto mutate) {
      VisibilityShard s = base;
      mutate(s);
      return decode_datagram(encode_datagram({kToken, 0, s}), out);
    };
    EXPECT_EQ(check([](VisibilityShard& s) { s.eye = static_cast<Eye>(2); }), DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.mask_bits = static_cast<MaskWidth>(12); }), DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.shard_index = s.shard_count; }), DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.shard_count = 0; }), DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.buffer_width = 0; }), DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.buffer_width = 5000; }), DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.pixel_count = 0; }), DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.first_pixel = 160 * 120 - s.pixel_count + 1; }),
              DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.first_pixel = UINT32_MAX; }), DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.scene_time_ns = -1; }), DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.scene_time_ns = INT64_MIN; }), DecodeError::kBadValue);
    EXPECT_EQ(check([](VisibilityShard& s) { s.scene_time_ns = INT64_MAX; }), DecodeError::kNone);
    EXPECT_EQ(check([](VisibilityShard& s) { s.view.pose.orientation = glm::dquat(0, 0, 0, 0); }),
              DecodeError::kBadPose);
    VisibilityShard s = base;
    s.payload_size = 0;
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, s}), out), DecodeError::kBadValue);
    s.payload_size = kMaxShardPayload + 1;
    EXPECT_TRUE(encode_datagram({kToken, 0, s}).empty());
  }
  {
    Heartbeat h;
    h.echo_delay_ns = -1;
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, h}), out), DecodeError::kBadValue);
    EXPECT_EQ(decode_datagram(encode_datagram({kToken, 0, Bye{static_cast<ByeReason>(kMaxByeReason + 1)}}), out),
              DecodeError::kBadValue);
  }
}

// NodeTransform (app-moved nodes): finite, stamp >= 0, unit rotation (renormalized), scale > 0, translation in range;
// in that order.
TEST(ProtocolRobustness, NodeTransformValuesAreValidated) {
  const NodeTransform base = std::get<NodeTransform>(sample_datagrams()[6].message);
  const auto check = [&](auto edit) {
    NodeTransform m = base;
    edit(m);
    Datagram out;
    return decode_datagram(encode_datagram({kToken, 0, m}), out);
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(check([](NodeTransform&) {}), DecodeError::kNone);
  EXPECT_EQ(check([&](NodeTransform& m) { m.trs.translation.y = nan; }), DecodeError::kNonFinite);
  EXPECT_EQ(check([&](NodeTransform& m) { m.trs.rotation.w = nan; }), DecodeError::kNonFinite);
  EXPECT_EQ(check([&](NodeTransform& m) { m.trs.scale.z = inf; }), DecodeError::kNonFinite);
  EXPECT_EQ(check([](NodeTransform& m) { m.scene_time_ns = -1; }), DecodeError::kBadValue);
  EXPECT_EQ(check([](NodeTransform& m) { m.scene_time_ns = 0; }), DecodeError::kNone);
  EXPECT_EQ(check([](NodeTransform& m) { m.trs.rotation = glm::dquat(0.9, 0.0, 0.0, 0.0); }), DecodeError::kBadPose);
  EXPECT_EQ(check([](NodeTransform& m) { m.trs.rotation = glm::dquat(0.0, 0.0, 0.0, 0.0); }), DecodeError::kBadPose);
  EXPECT_EQ(check([](NodeTransform& m) { m.trs.scale.x = 0.0; }), DecodeError::kBadValue);
  EXPECT_EQ(check([](NodeTransform& m) { m.trs.scale.y = -1.0; }), DecodeError::kBadValue);
  EXPECT_EQ(check([](NodeTransform& m) { m.trs.translation.x = 2.0e6; }), DecodeError::kBadPose);
  // NaN first: a NaN stamp cannot exist, but a NaN rotation with a negative stamp is non-finite.
  EXPECT_EQ(check([&](NodeTransform& m) {
              m.scene_time_ns = -5;
              m.trs.rotation.x = nan;
            }),
            DecodeError::kNonFinite);
  // A rotation off unit within the tolerance is accepted and renormalized.
  NodeTransform m = base;
  m.trs.rotation = glm::dquat(0.8002, 0.0, 0.6, 0.0);
  Datagram out;
  ASSERT_EQ(decode_datagram(encode_datagram({kToken, 0, m}), out), DecodeError::kNone);
  EXPECT_NEAR(glm::length(std::get<NodeTransform>(out.message).trs.rotation), 1.0, 1e-12);
  EXPECT_FALSE(node_transform_as_decoded(NodeTransform{1, -1, base.trs}).has_value());
}

TEST(ProtocolRobustness, RandomCorruptionNeverCrashes) {
  uint64_t state = 12345;
  auto next = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint32_t>(state >> 33);
  };
  size_t accepted = 0, rejected = 0;
  DecodeErrorCounts counts;
  for (const Datagram& d : sample_datagrams()) {
    const Bytes good = encode_datagram(d);
    for (int iter = 0; iter < 4000; ++iter) {
      Bytes b = good;
      const int flips = 1 + static_cast<int>(next() % 4);
      for (int f = 0; f < flips; ++f) b[next() % b.size()] ^= static_cast<uint8_t>(1u << (next() % 8));
      if (next() % 8 == 0) b.resize(next() % (b.size() + 1));
      Datagram out;
      const DecodeError e = decode_datagram(b, out);
      counts.add(e);
      if (e == DecodeError::kNone) {
        ++accepted;
        // Whatever is accepted must be a well-formed message again.
        EXPECT_FALSE(encode_datagram(out).empty());
      } else {
        ++rejected;
      }
    }
  }
  EXPECT_GT(rejected, 0u);
  EXPECT_EQ(accepted + rejected, sample_datagrams().size() * 4000u);
  EXPECT_EQ(counts.total_errors(), rejected);
}

TEST(ProtocolRobustness, GarbageNeverCrashes) {
  uint64_t state = 777;
  for (int iter = 0; iter < 20000; ++iter) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    Bytes b(static_cast<size_t>(state >> 54));  // 0..1023 bytes
    for (auto& x : b) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      x = static_cast<uint8_t>(state >> 56);
    }
    if (b.size() >= 6 && iter % 2 == 0) {  // valid magic/version/type so the body decoders get exercised
      b[0] = 'D';
      b[1] = 'H';
      b[2] = 'R';
      b[3] = 'X';
      b[4] = kProtocolVersion;
      b[5] = static_cast<uint8_t>(1 + iter % 6);
      if (b.size() >= 8) b[6] = b[7] = 0;
    }
    Datagram out;
    (void)decode_datagram(b, out);
  }
  SUCCEED();
}

TEST(ProtocolRobustness, EncodeIntoSmallBufferFails) {
  const Datagram d = sample_datagrams()[2];
  std::vector<uint8_t> buf(encoded_size(d.message) - 1);
  EXPECT_EQ(encode_datagram(d, buf), 0u);
  buf.resize(encoded_size(d.message));
  EXPECT_EQ(encode_datagram(d, buf), buf.size());
}

TEST(ProtocolRobustness, ErrorNamesAreDistinct) {
  for (size_t i = 0; i < kDecodeErrorCount; ++i)
    for (size_t j = i + 1; j < kDecodeErrorCount; ++j)
      EXPECT_STRNE(to_string(static_cast<DecodeError>(i)), to_string(static_cast<DecodeError>(j)));
}

}  // namespace
}  // namespace dhr
