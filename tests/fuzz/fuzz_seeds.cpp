// Seed inputs for the fuzz targets, made with the project's own encoders (so they follow the current
// wire format without committed binary files). Scene seeds are in fuzz_seeds_scene.cpp.
#include "codec/codec.hpp"
#include "codec/codec_v2.hpp"
#include "traces/pose_trace.hpp"
#include "traces/shown_frame.hpp"
#include "protocol/protocol.hpp"
#include "metrics/visibility_synthetic.hpp"
#include "fuzz_layouts.hpp"
#include "fuzz_support.hpp"
#include "protocol_fixtures.hpp"
#include "secure/envelope.hpp"
#include "secure/key.hpp"
#include "visibility/visibility_layout.hpp"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cstring>
#include <limits>

namespace dhr::fuzz {

std::vector<Seed> scene_seeds();  // fuzz_seeds_scene.cpp

namespace {

Bytes datagram(uint64_t token, const Message& message) { return encode_datagram(Datagram{token, 9, message}); }

std::vector<Seed> datagram_seeds() {
  std::vector<Seed> out;
  // One of each message type (the protocol unit tests' samples), named after its type.
  const std::vector<Datagram> samples = test::sample_datagrams();
  for (const Datagram& d : samples) out.push_back({to_string(message_type(d.message)), encode_datagram(d)});
  // Small shards: the first and last of a room buffer cut into 200-byte payloads.
  const VisibilityBuffer vis = make_room_visibility(64, 32, 3, 1);
  EncodeOptions options;
  options.max_payload = 200;
  const auto shards = make_visibility_shards(vis, 1234, Eye::kRight, test::sample_view(0.3), options);
  if (!shards.empty()) {
    out.push_back({"shard_first", datagram(77, shards.front())});
    out.push_back({"shard_last", datagram(77, shards.back())});
  }
  out.push_back({"bye_to_hello", datagram(0, Bye{ByeReason::kVersionMismatch})});
  // Soft levels (protocol version 4): a Hello offering them, a Welcome granting them (2 of 3 lights: 7 bits).
  Hello soft_hello = std::get<Hello>(samples.front().message);
  soft_hello.capabilities |= kCapabilityCodecV2 | kCapabilitySoftLevels;
  out.push_back({"hello_soft_levels", datagram(0, soft_hello)});
  Welcome soft_welcome = std::get<Welcome>(samples[1].message);
  soft_welcome.capabilities |= kCapabilitySoftLevels;
  soft_welcome.light_count = 3;
  soft_welcome.soft_light_count = 2;
  soft_welcome.mask_bits = MaskWidth::k8;
  out.push_back({"welcome_soft_levels", datagram(77, soft_welcome)});
  // Scene time (protocol version 5): a pose and a shard at a late scene time (an animation's later keys).
  PoseUpdate late_pose = std::get<PoseUpdate>(samples[2].message);
  late_pose.scene_time_ns = 3'600'000'000'000;
  out.push_back({"pose_late_scene_time", datagram(77, late_pose)});
  if (!shards.empty()) {
    VisibilityShard late_shard = shards.front();
    late_shard.scene_time_ns = 3'600'000'000'000;
    out.push_back({"shard_late_scene_time", datagram(77, late_shard)});
  }
  // App-moved nodes (protocol version 6; the samples hold one "NodeTransform"): one at the largest stamp.
  NodeTransform far = std::get<NodeTransform>(samples[6].message);
  far.scene_time_ns = std::numeric_limits<int64_t>::max();
  out.push_back({"node_transform_far_scene_time", datagram(77, far)});
  Bytes other_version = encode_datagram(samples.front());
  if (other_version.size() > 4) other_version[4] = kProtocolVersion + 1;
  out.push_back({"hello_version2", other_version});
  return out;
}

// The fixed key of fuzz_secure_datagram.cpp.
secure::Key fuzz_key() {
  std::array<uint8_t, secure::kKeySize> bytes{};
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<uint8_t>(i * 7 + 1);
  return secure::Key(bytes);
}

std::vector<Seed> secure_datagram_seeds() {
  std::vector<Seed> out;
  const secure::Key key = fuzz_key();
  const secure::HandshakeKey handshake(key);
  for (const Datagram& d : test::sample_datagrams()) {
    const Bytes plain = encode_datagram(d);
    Bytes sealed(plain.size() + secure::kSealTagSize);
    if (secure::seal(key, plain, sealed) > 0) out.push_back({std::string("sealed_") + to_string(message_type(d.message)), sealed});
    Bytes tagged(plain.size() + secure::kHandshakeTrailerSize);
    std::copy(plain.begin(), plain.end(), tagged.begin());
    secure::Random random{};
    random[0] = 42;
    if (handshake.authenticate(tagged, plain.size(), random) > 0)
      out.push_back({std::string("tagged_") + to_string(message_type(d.message)), tagged});
  }
  return out;
}

std::vector<Seed> key_file_seeds() {
  const std::string text = "# deployment key\n" + secure::format_key(fuzz_key());
  return {{"key", Bytes(text.begin(), text.end())}, {"empty", Bytes{}}};
}

std::vector<Seed> shown_frame_seeds() {
  ShownFrame f;
  f.frame = 100;
  f.eye_size = {160, 120};
  f.traced = TracedFormat{f.eye_size, GuardBand{3, 2}};
  f.scene_hash = 0x0123456789abcdefull;
  f.render_path = "forward";
  f.warp = "paper";
  for (int e = 0; e < 2; ++e) {
    f.eyes[e].view.pose.position = {0.03 * (2 * e - 1), 1.6, 0.0};
    f.eyes[e].file = e == 0 ? "frame_000100_left.png" : "frame_000100_right.png";
    f.eyes[e].has_visibility = true;
    f.eyes[e].visibility_frame = 99;
    f.eyes[e].age = 1;
    f.eyes[e].complete = true;
  }
  const std::string line = shown_frame_json(f);
  f.traced.reset();
  f.scene_hash.reset();
  f.eyes[1].has_visibility = false;
  const std::string without = shown_frame_json(f);
  return {{"frame", Bytes(line.begin(), line.end())}, {"no_session", Bytes(without.begin(), without.end())}};
}

struct TestBuffer {
  const char* name;
  VisibilityBuffer buffer;
};

std::vector<TestBuffer> small_buffers() {
  return {{"room8", make_room_visibility(64, 32, 3, 7)},
          {"stripes16", make_stripe_visibility(48, 20, 12, 9)},
          {"random32", make_random_visibility(16, 8, 20, 3)},
          {"uniform8", make_uniform_visibility(40, 10, 5, 0x15)}};
}

uint8_t mask_mode(MaskWidth w) { return w == MaskWidth::k8 ? 0 : w == MaskWidth::k16 ? 1 : 2; }

std::vector<Seed> shard_payload_seeds() {
  std::vector<Seed> out;
  for (const TestBuffer& t : small_buffers()) {
    EncodeOptions options;
    options.max_payload = 160;
    std::vector<EncodedShard> shards;
    if (!encode_visibility(t.buffer, options, shards)) continue;
    for (size_t i = 0; i < shards.size() && i < 3; ++i) {
      ShardPayloadParams p;
      p.mode = mask_mode(t.buffer.mask_bits);
      p.width = t.buffer.width;
      p.height = t.buffer.height;
      p.first_pixel = shards[i].first_pixel;
      p.pixel_count = shards[i].pixel_count;
      Bytes b;
      p.write(b);
      put_bytes(b, shards[i].payload);
      out.push_back({std::string(t.name) + "_" + std::to_string(i), std::move(b)});
    }
  }
  return out;
}

// Seeds of the first `limit` v2 shards of `shards` (v1 fallbacks skipped), named prefix_i.
void add_v2_shard_seeds(ShardPayloadV2Params p, const std::vector<EncodedShard>& shards, size_t limit,
                        const std::string& prefix, std::vector<Seed>& out) {
  for (size_t i = 0; i < shards.size() && i < limit; ++i) {
    if (!is_v2_payload(shards[i].payload)) continue;
    p.first_row = shards[i].first_pixel / p.width;
    p.rows = shards[i].pixel_count / p.width;
    Bytes b;
    p.write(b);
    put_bytes(b, shards[i].payload);
    out.push_back({prefix + "_" + std::to_string(i), std::move(b)});
  }
}

std::vector<Seed> shard_payload_v2_seeds() {
  std::vector<Seed> out;
  for (const uint8_t mode : {uint8_t{0}, uint8_t{4}, uint8_t{1}, uint8_t{5}}) {  // 3 / 9 lights, intra / inter
    ShardPayloadV2Params p;
    p.mode = mode;
    p.width = 100;
    p.height = 40;
    const VisibilityBuffer ref = v2_fuzz_reference(p.width, p.height, p.light_count());
    VisibilityBuffer cur = VisibilityBuffer::create(p.width, p.height, p.light_count());
    for (uint32_t y = 0; y < p.height; ++y)  // the reference moved one pixel right, plus a square of light
      for (uint32_t x = 0; x < p.width; ++x)
        cur.set(x, y, (x > 0 ? ref.get(x - 1, y) : 0u) | (x > 40 && x < 60 && y > 10 && y < 30 ? 1u : 0u));
    const V2Reference r{&ref, 1};
    EncodeOptions options;
    options.max_payload = 120;
    std::vector<EncodedShard> shards;
    if (!encode_visibility_v2(cur, 2, (mode & 4) ? &r : nullptr, options, shards)) continue;
    add_v2_shard_seeds(p, shards, 3, "v2_mode" + std::to_string(mode), out);
  }
  // Soft levels: 3 soft lights (9 bits, mode 1), each field the Gray code of a level ramp across a penumbra.
  {
    ShardPayloadV2Params p;
    p.mode = 1;
    p.width = 100;
    p.height = 40;
    const bool soft[3] = {true, true, true};
    const VisibilityLayout layout = VisibilityLayout::for_lights(soft);
    VisibilityBuffer cur = VisibilityBuffer::create(p.width, p.height, layout.total_bits());
    for (uint32_t y = 0; y < p.height; ++y)
      for (uint32_t x = 0; x < p.width; ++x) {
        uint32_t m = 0;
        for (uint32_t l = 0; l < 3; ++l)
          m = layout.with_visibility(m, l, std::clamp((static_cast<float>(x + 7 * l) - 30.0f) / 25.0f, 0.0f, 1.0f));
        cur.set(x, y, m);
      }
    EncodeOptions options;
    options.max_payload = 120;
    std::vector<EncodedShard> shards;
    if (encode_visibility_v2(cur, 2, nullptr, options, shards)) add_v2_shard_seeds(p, shards, 2, "v2_soft9", out);
  }
  return out;
}

std::vector<Seed> codec_roundtrip_seeds() {
  std::vector<Seed> out;
  auto add = [&](const char* name, CodecRoundTripParams p, const Bytes& fill) {
    Bytes b;
    p.write(b);
    put_bytes(b, fill);
    out.push_back({name, std::move(b)});
  };
  CodecRoundTripParams p;
  p.light_count = 3;
  p.width = 120;
  p.height = 40;
  p.max_payload = static_cast<uint16_t>(kMaxShardPayload);
  p.uniform_min_bytes = 8192;
  // Runs: 2000 dark, 37 of mask 5, 300 of mask 7, 1 of mask 1 (u16 length - 1, then one mask byte).
  add("runs8", p, {0xCF, 0x07, 0x00, 36, 0, 5, 0x2B, 0x01, 7, 0, 0, 1});
  p.light_count = 12;
  p.max_payload = 200;
  p.row_aligned = true;
  add("runs16_aligned", p, {0x0F, 0x00, 0x34, 0x12, 0x00, 0x00, 0xFF, 0x0F, 0x03, 0x00, 0x01, 0x00});
  p.light_count = 20;
  p.fill = CodecRoundTripParams::kCyclic;
  p.max_payload = 64;
  p.uniform_min_bytes = 32;
  Bytes noise;
  Prng rng(5);
  for (int i = 0; i < 61; ++i) noise.push_back(static_cast<uint8_t>(rng.next()));
  add("cyclic32", p, noise);
  p.light_count = 2;
  p.fill = CodecRoundTripParams::kSparse;
  p.row_aligned = false;
  p.max_payload = 1000;
  add("sparse8", p, {200, 3, 17, 1, 250, 2});
  p.width = 1;
  p.height = 1;
  add("tiny", p, {});
  return out;
}

std::vector<Seed> reassembler_seeds() {
  std::vector<Seed> out;
  ReassemblerParams p;
  p.width = 64;
  p.height = 24;
  p.light_count = 3;
  p.frames_in_flight = 3;
  p.max_payload = 200;
  auto real = [](Bytes& b, uint8_t frame, uint8_t eye, uint16_t index) {
    put_u8(b, static_cast<uint8_t>(ReassemblerOp::kGenuine));
    put_u8(b, frame);
    put_u8(b, eye);
    put_u16(b, index);
  };
  {  // frame 1 in order, frame 2 with shard 1 lost, frame 3 of the right eye backwards, a late frame 1 shard
    Bytes b;
    p.write(b);
    for (uint16_t i = 0; i < 12; ++i) real(b, 1, 0, i);
    for (uint16_t i = 0; i < 12; ++i)
      if (i != 1) real(b, 2, 0, i);
    for (uint16_t i = 12; i-- > 0;) real(b, 3, 1, i);
    real(b, 1, 0, 4);
    out.push_back({"in_order_loss_reverse", std::move(b)});
  }
  {  // more frames than slots, then a duplicate, a reset, and forged shards
    Bytes b;
    p.frames_in_flight = 2;
    p.write(b);
    for (uint8_t f = 1; f <= 6; ++f) real(b, f, 0, 0);
    for (uint16_t i = 0; i < 12; ++i) real(b, 5, 0, i);
    put_u8(b, static_cast<uint8_t>(ReassemblerOp::kControl) | (1 << 2));  // re-insert the previous shard
    put_u8(b, static_cast<uint8_t>(ReassemblerOp::kForged));
    // flags, frame, eye, donor shard (u16), view, index (u16), first (u32), count (u32), then flags & 8:
    // the donor's payload with byte (u16) xor (u8); else a payload of (u16) bytes. See forged_shard().
    put_bytes(b, Bytes{0x08, 7, 0, 2, 0, 9, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 5, 0, 0x40});
    put_u8(b, static_cast<uint8_t>(ReassemblerOp::kForged));
    put_bytes(b, Bytes{0x00, 8, 1, 0, 0, 5, 0, 0, 0, 0, 0, 0, 15, 0, 0, 0, 6, 0, 0, 16, 0, 0, 0, 5});
    put_u8(b, static_cast<uint8_t>(ReassemblerOp::kControl));  // reset
    for (uint16_t i = 0; i < 12; ++i) real(b, 2, 1, i);
    out.push_back({"slots_dup_forged_reset", std::move(b)});
  }
  {  // a newest-requested limit, 16-bit masks, small shards
    Bytes b;
    p.light_count = 9;
    p.max_payload = 64;
    p.limit_frames = true;
    p.newest_requested = 4;
    p.write(b);
    for (uint8_t f = 3; f <= 5; ++f)
      for (uint16_t i = 0; i < 40; ++i) real(b, f, f & 1, i);
    out.push_back({"limit_16bit", std::move(b)});
  }
  return out;
}

Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

std::vector<Seed> pose_trace_seeds() {
  std::vector<Seed> out;
  PoseTrace trace;
  trace.comments.push_back("seed trace");
  for (int i = 0; i < 4; ++i) {
    TraceSample s;
    s.time = 0.011 * i;
    s.head.position = {0.01 * i, 1.6, -0.02 * i};
    s.head.orientation = glm::angleAxis(0.05 * i, glm::dvec3(0.0, 1.0, 0.0));
    s.eye[0] = s.head;
    s.eye[1] = s.head;
    s.eye[0].position.x -= 0.0315;
    s.eye[1].position.x += 0.0315;
    s.fov[0] = Fov{-0.8f, 0.75f, 0.7f, -0.72f};
    s.fov[1] = Fov{-0.75f, 0.8f, 0.7f, -0.72f};
    trace.samples.push_back(s);
  }
  out.push_back({"canonical_head.csv", text(format_canonical_trace(trace))});
  trace.has_eye_poses = true;
  trace.has_fov = true;
  out.push_back({"canonical_eyes_fov.csv", text(format_canonical_trace(trace))});
  out.push_back({"gul_raw.csv", text("timestamp,x,y,z,qx,qy,qz,qw\n"
                                     "637139238387771648, 0.0053, 0.0704, 0.0825, 0.0538, 0.0061, -0.0192, 0.9983\n"
                                     "637139238388383989, 0.0061, 0.0697, 0.0820, 0.0558, 0.0037, -0.0179, 0.9983\n"
                                     "637139238388994000, 0.0062, 0.0696, 0.0821, 0.0560, 0.0036, -0.0178, 0.9")});
  out.push_back({"gul_interp.csv", text("timestamp,x,y,z,qx,qy,qz,qw,roll,pitch,yaw\n"
                                        "0.0,0.0053,0.0704,0.0825,0.0538,0.0061,-0.0192,0.9983,-2.25,6.15,0.82\n"
                                        "5000000.0,0.0054,0.0703,0.0825,0.0540,0.0059,-0.0191,0.9983,-2.24,6.17,0.80\n")});
  out.push_back({"nasrabadi.csv", text("0,0.076362,-0.0043327,-0.034734,0.99647,-0.01394,0.15188,0.9883\n"
                                       "0.018,0.077247,-0.0054199,-0.036663,0.99632,-0.016464,0.15353,0.98801\n")});
  return out;
}

}  // namespace

std::vector<std::string> seed_targets() {
  return {"datagram",   "shard_payload", "shard_payload_v2", "codec_roundtrip", "reassembler",
          "scene",      "pose_trace",    "secure_datagram",  "key_file",        "shown_frame"};
}

std::vector<Seed> seeds_for(const std::string& target) {
  if (target == "datagram") return datagram_seeds();
  if (target == "shard_payload") return shard_payload_seeds();
  if (target == "shard_payload_v2") return shard_payload_v2_seeds();
  if (target == "codec_roundtrip") return codec_roundtrip_seeds();
  if (target == "reassembler") return reassembler_seeds();
  if (target == "scene") return scene_seeds();
  if (target == "pose_trace") return pose_trace_seeds();
  if (target == "secure_datagram") return secure_datagram_seeds();
  if (target == "key_file") return key_file_seeds();
  if (target == "shown_frame") return shown_frame_seeds();
  return {};
}

}  // namespace dhr::fuzz
