#include "protocol/protocol.hpp"

#include "protocol/byte_io.hpp"

#include <cmath>
#include <type_traits>

namespace dhr {
namespace {

constexpr size_t kHelloFixed = 22;
constexpr size_t kWelcomeBody = 36;
constexpr size_t kPoseUpdateBody = 16 + 2 * kViewWireSize + 4;
constexpr size_t kShardBodyFixed = 28 + kViewWireSize;
constexpr size_t kHeartbeatBody = 52;
constexpr size_t kByeBody = 1;
static_assert(kHeaderSize + kShardBodyFixed == kShardFixedSize);

// ---- views -------------------------------------------------------------------------------------

void write_view(ByteWriter& w, const View& v) {
  w.f64(v.pose.position.x);
  w.f64(v.pose.position.y);
  w.f64(v.pose.position.z);
  // Quaternion in OpenXR order (x, y, z, w); float precision (~1e-7 rad) is far below a pixel.
  w.f32(static_cast<float>(v.pose.orientation.x));
  w.f32(static_cast<float>(v.pose.orientation.y));
  w.f32(static_cast<float>(v.pose.orientation.z));
  w.f32(static_cast<float>(v.pose.orientation.w));
  w.f32(v.fov.angle_left);
  w.f32(v.fov.angle_right);
  w.f32(v.fov.angle_up);
  w.f32(v.fov.angle_down);
}

struct RawView {
  double p[3];
  float q[4];  // x, y, z, w
  float fov[4];
};

RawView read_view(ByteReader& r) {
  RawView v{};
  for (double& x : v.p) x = r.f64();
  for (float& x : v.q) x = r.f32();
  for (float& x : v.fov) x = r.f32();
  return v;
}

DecodeError decode_view(const RawView& raw, View& out) {
  for (double x : raw.p)
    if (!std::isfinite(x)) return DecodeError::kNonFinite;
  for (float x : raw.q)
    if (!std::isfinite(x)) return DecodeError::kNonFinite;
  for (float x : raw.fov)
    if (!std::isfinite(x)) return DecodeError::kNonFinite;
  Pose pose;
  pose.position = glm::dvec3(raw.p[0], raw.p[1], raw.p[2]);
  pose.orientation = glm::dquat(static_cast<double>(raw.q[3]), static_cast<double>(raw.q[0]),
                                static_cast<double>(raw.q[1]), static_cast<double>(raw.q[2]));
  if (validate_pose(pose)) return DecodeError::kBadPose;
  const glm::dquat& q = pose.orientation;
  const double norm2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  if (std::fabs(norm2 - 1.0) > kQuaternionNormTolerance) return DecodeError::kBadPose;
  Fov fov{raw.fov[0], raw.fov[1], raw.fov[2], raw.fov[3]};
  if (validate_fov(fov)) return DecodeError::kBadFov;
  out.pose = normalized(pose);
  out.fov = fov;
  return DecodeError::kNone;
}

// ---- bodies ------------------------------------------------------------------------------------

void write_body(ByteWriter& w, const Hello& m) {
  w.u64(m.client_nonce);
  w.u32(m.capabilities);
  w.u16(m.eye_width);
  w.u16(m.eye_height);
  w.u16(m.guard_x);
  w.u16(m.guard_y);
  w.u8(m.light_count_wanted);
  w.u8(static_cast<uint8_t>(m.scene_id.size()));
  w.bytes(std::span(reinterpret_cast<const uint8_t*>(m.scene_id.data()), m.scene_id.size()));
}

void write_body(ByteWriter& w, const Welcome& m) {
  w.u64(m.client_nonce);
  w.u32(m.capabilities);
  w.u64(m.scene_hash);
  w.u8(m.light_count);
  w.u8(static_cast<uint8_t>(m.mask_bits));
  w.u16(m.buffer_width);
  w.u16(m.buffer_height);
  w.u16(m.guard_x);
  w.u16(m.guard_y);
  w.u16(m.heartbeat_interval_ms);
  w.u32(m.session_timeout_ms);
}

void write_body(ByteWriter& w, const PoseUpdate& m) {
  w.u64(m.frame);
  w.i64(m.display_time_ns);
  write_view(w, m.views[0]);
  write_view(w, m.views[1]);
  w.u16(m.held_distance[0]);
  w.u16(m.held_distance[1]);
}

void write_body(ByteWriter& w, const VisibilityShard& m) {
  w.u64(m.frame_number);
  w.u8(static_cast<uint8_t>(m.eye));
  w.u8(static_cast<uint8_t>(m.mask_bits));
  w.u16(m.shard_index);
  w.u16(m.shard_count);
  w.u16(m.buffer_width);
  w.u16(m.buffer_height);
  w.u16(m.payload_size);
  w.u32(m.first_pixel);
  w.u32(m.pixel_count);
  write_view(w, m.view);
  w.bytes(m.payload_bytes());
}

void write_body(ByteWriter& w, const Heartbeat& m) {
  w.i64(m.send_time_ns);
  w.i64(m.echo_time_ns);
  w.i64(m.echo_delay_ns);
  w.u64(m.newest_frame);
  w.u32(m.datagrams_sent);
  w.u32(m.datagrams_received);
  w.u32(m.datagrams_rejected);
  w.u32(m.frames_done);
  w.u32(m.frames_dropped);
}

void write_body(ByteWriter& w, const Bye& m) { w.u8(static_cast<uint8_t>(m.reason)); }

bool valid_traced_size(uint32_t eye, uint32_t guard) {
  return eye >= 1 && eye + 2u * guard <= kMaxBufferDimension;
}

DecodeError read_body(ByteReader& r, Hello& m) {
  m.client_nonce = r.u64();
  m.capabilities = r.u32();
  m.eye_width = r.u16();
  m.eye_height = r.u16();
  m.guard_x = r.u16();
  m.guard_y = r.u16();
  m.light_count_wanted = r.u8();
  const uint8_t scene_len = r.u8();
  if (!r.ok()) return DecodeError::kTruncated;
  if (scene_len > kMaxSceneIdLength) return DecodeError::kBadString;
  const auto scene = r.bytes(scene_len);
  if (!r.ok()) return DecodeError::kTruncated;
  for (uint8_t c : scene)
    if (c < 0x20 || c == 0x7F) return DecodeError::kBadString;
  m.scene_id.assign(reinterpret_cast<const char*>(scene.data()), scene.size());
  if (!valid_traced_size(m.eye_width, m.guard_x) || !valid_traced_size(m.eye_height, m.guard_y))
    return DecodeError::kBadValue;
  if (m.light_count_wanted > kMaxLights) return DecodeError::kBadValue;
  return DecodeError::kNone;
}

DecodeError read_body(ByteReader& r, Welcome& m) {
  m.client_nonce = r.u64();
  m.capabilities = r.u32();
  m.scene_hash = r.u64();
  m.light_count = r.u8();
  const uint8_t mask_bits = r.u8();
  m.buffer_width = r.u16();
  m.buffer_height = r.u16();
  m.guard_x = r.u16();
  m.guard_y = r.u16();
  m.heartbeat_interval_ms = r.u16();
  m.session_timeout_ms = r.u32();
  if (!r.ok()) return DecodeError::kTruncated;
  if (m.light_count > kMaxLights) return DecodeError::kBadValue;
  const auto width = mask_width_from_bits(mask_bits);
  if (!width || *width != mask_width_for_light_count(m.light_count)) return DecodeError::kBadValue;
  m.mask_bits = *width;
  if (m.buffer_width < 1 || m.buffer_width > kMaxBufferDimension || m.buffer_height < 1 ||
      m.buffer_height > kMaxBufferDimension)
    return DecodeError::kBadValue;
  if (2u * m.guard_x >= m.buffer_width || 2u * m.guard_y >= m.buffer_height) return DecodeError::kBadValue;
  if (m.heartbeat_interval_ms == 0 || m.session_timeout_ms == 0) return DecodeError::kBadValue;
  return DecodeError::kNone;
}

DecodeError read_body(ByteReader& r, PoseUpdate& m) {
  m.frame = r.u64();
  m.display_time_ns = r.i64();
  const RawView left = read_view(r);
  const RawView right = read_view(r);
  m.held_distance[0] = r.u16();
  m.held_distance[1] = r.u16();
  if (!r.ok()) return DecodeError::kTruncated;
  if (m.display_time_ns < 0) return DecodeError::kBadValue;
  if (const DecodeError e = decode_view(left, m.views[0]); e != DecodeError::kNone) return e;
  return decode_view(right, m.views[1]);
}

DecodeError read_body(ByteReader& r, VisibilityShard& m) {
  m.frame_number = r.u64();
  const uint8_t eye = r.u8();
  const uint8_t mask_bits = r.u8();
  m.shard_index = r.u16();
  m.shard_count = r.u16();
  m.buffer_width = r.u16();
  m.buffer_height = r.u16();
  m.payload_size = r.u16();
  m.first_pixel = r.u32();
  m.pixel_count = r.u32();
  const RawView view = read_view(r);
  if (!r.ok()) return DecodeError::kTruncated;
  if (m.payload_size < 1 || m.payload_size > kMaxShardPayload) return DecodeError::kBadValue;
  const auto payload = r.bytes(m.payload_size);
  if (!r.ok()) return DecodeError::kTruncated;
  if (eye > 1) return DecodeError::kBadValue;
  m.eye = static_cast<Eye>(eye);
  const auto width = mask_width_from_bits(mask_bits);
  if (!width) return DecodeError::kBadValue;
  m.mask_bits = *width;
  if (m.shard_count < 1 || m.shard_index >= m.shard_count) return DecodeError::kBadValue;
  if (m.buffer_width < 1 || m.buffer_width > kMaxBufferDimension || m.buffer_height < 1 ||
      m.buffer_height > kMaxBufferDimension)
    return DecodeError::kBadValue;
  const uint64_t pixels = uint64_t{m.buffer_width} * m.buffer_height;
  if (m.pixel_count < 1 || uint64_t{m.first_pixel} + m.pixel_count > pixels) return DecodeError::kBadValue;
  if (const DecodeError e = decode_view(view, m.view); e != DecodeError::kNone) return e;
  for (size_t i = 0; i < payload.size(); ++i) m.payload[i] = payload[i];
  return DecodeError::kNone;
}

DecodeError read_body(ByteReader& r, Heartbeat& m) {
  m.send_time_ns = r.i64();
  m.echo_time_ns = r.i64();
  m.echo_delay_ns = r.i64();
  m.newest_frame = r.u64();
  m.datagrams_sent = r.u32();
  m.datagrams_received = r.u32();
  m.datagrams_rejected = r.u32();
  m.frames_done = r.u32();
  m.frames_dropped = r.u32();
  if (!r.ok()) return DecodeError::kTruncated;
  if (m.send_time_ns < 0 || m.echo_time_ns < 0 || m.echo_delay_ns < 0) return DecodeError::kBadValue;
  return DecodeError::kNone;
}

DecodeError read_body(ByteReader& r, Bye& m) {
  const uint8_t reason = r.u8();
  if (!r.ok()) return DecodeError::kTruncated;
  if (reason > kMaxByeReason) return DecodeError::kBadValue;
  m.reason = static_cast<ByeReason>(reason);
  return DecodeError::kNone;
}

size_t body_size(const Hello& m) { return kHelloFixed + m.scene_id.size(); }
size_t body_size(const Welcome&) { return kWelcomeBody; }
size_t body_size(const PoseUpdate&) { return kPoseUpdateBody; }
size_t body_size(const VisibilityShard& m) { return kShardBodyFixed + m.payload_size; }
size_t body_size(const Heartbeat&) { return kHeartbeatBody; }
size_t body_size(const Bye&) { return kByeBody; }

bool representable(const Hello& m) { return m.scene_id.size() <= kMaxSceneIdLength; }
bool representable(const VisibilityShard& m) { return m.payload_size <= kMaxShardPayload; }
template <class T>
bool representable(const T&) {
  return true;
}

// Token rules: Hello has none yet; a Bye may answer a Hello (token 0); everything else needs one.
bool token_ok(MessageType type, uint64_t token) {
  if (type == MessageType::kHello) return token == 0;
  if (type == MessageType::kBye) return true;
  return token != 0;
}

}  // namespace

MessageType message_type(const Message& message) {
  return static_cast<MessageType>(message.index() + 1);
}

const char* to_string(MessageType type) {
  switch (type) {
    case MessageType::kHello: return "Hello";
    case MessageType::kWelcome: return "Welcome";
    case MessageType::kPoseUpdate: return "PoseUpdate";
    case MessageType::kVisibilityShard: return "VisibilityShard";
    case MessageType::kHeartbeat: return "Heartbeat";
    case MessageType::kBye: return "Bye";
  }
  return "unknown";
}

const char* to_string(ByeReason reason) {
  switch (reason) {
    case ByeReason::kNormal: return "normal";
    case ByeReason::kTimeout: return "timeout";
    case ByeReason::kProtocolError: return "protocol error";
    case ByeReason::kShutdown: return "shutdown";
    case ByeReason::kVersionMismatch: return "version mismatch";
    case ByeReason::kUnknownSession: return "unknown session";
    case ByeReason::kBadHello: return "bad hello";
    case ByeReason::kUnknownScene: return "unknown scene";
    case ByeReason::kAuthRequired: return "authentication required";
    case ByeReason::kAuthFailed: return "authentication failed";
  }
  return "unknown";
}

size_t encoded_size(const Message& message) {
  return kHeaderSize + std::visit([](const auto& m) { return body_size(m); }, message);
}

size_t encode_datagram(const Datagram& datagram, std::span<uint8_t> out) {
  const bool ok = std::visit([](const auto& m) { return representable(m); }, datagram.message);
  const size_t size = encoded_size(datagram.message);
  if (!ok || size > out.size()) return 0;
  ByteWriter w(out);
  w.bytes(kProtocolMagic);
  w.u8(kProtocolVersion);
  w.u8(static_cast<uint8_t>(message_type(datagram.message)));
  w.u16(0);  // reserved
  w.u64(datagram.session_token);
  w.u32(datagram.sequence);
  std::visit([&w](const auto& m) { write_body(w, m); }, datagram.message);
  return w.ok() && w.size() == size ? size : 0;
}

std::vector<uint8_t> encode_datagram(const Datagram& datagram) {
  std::vector<uint8_t> out(encoded_size(datagram.message));
  const size_t n = encode_datagram(datagram, out);
  out.resize(n);
  return out;
}

DecodeError decode_header(std::span<const uint8_t> bytes, DatagramHeader& out) {
  if (bytes.size() > kMaxDatagramSize) return DecodeError::kOversize;
  ByteReader r(bytes);
  const auto magic = r.bytes(kProtocolMagic.size());
  if (!r.ok()) return DecodeError::kTruncated;
  for (size_t i = 0; i < kProtocolMagic.size(); ++i)
    if (magic[i] != kProtocolMagic[i]) return DecodeError::kBadMagic;
  out.version = r.u8();
  if (!r.ok()) return DecodeError::kTruncated;
  // Checked before the rest so a peer of another version is recognised even if its header differs.
  if (out.version != kProtocolVersion) return DecodeError::kWrongVersion;
  const uint8_t type = r.u8();
  const uint16_t reserved = r.u16();
  out.session_token = r.u64();
  out.sequence = r.u32();
  if (!r.ok()) return DecodeError::kTruncated;
  if (type < static_cast<uint8_t>(MessageType::kHello) || type > static_cast<uint8_t>(MessageType::kBye))
    return DecodeError::kUnknownType;
  out.type = static_cast<MessageType>(type);
  if (reserved != 0) return DecodeError::kBadReserved;
  if (!token_ok(out.type, out.session_token)) return DecodeError::kBadToken;
  return DecodeError::kNone;
}

namespace {
template <class T>
DecodeError decode_into(ByteReader& r, Datagram& out) {
  T& m = out.message.emplace<T>();
  const DecodeError e = read_body(r, m);
  if (e != DecodeError::kNone) return e;
  return r.at_end() ? DecodeError::kNone : DecodeError::kTrailingBytes;
}
}  // namespace

DecodeError decode_datagram(std::span<const uint8_t> bytes, Datagram& out) {
  DatagramHeader header;
  if (const DecodeError e = decode_header(bytes, header); e != DecodeError::kNone) return e;
  out.session_token = header.session_token;
  out.sequence = header.sequence;
  ByteReader r(bytes.subspan(kHeaderSize));
  switch (header.type) {
    case MessageType::kHello: return decode_into<Hello>(r, out);
    case MessageType::kWelcome: return decode_into<Welcome>(r, out);
    case MessageType::kPoseUpdate: return decode_into<PoseUpdate>(r, out);
    case MessageType::kVisibilityShard: return decode_into<VisibilityShard>(r, out);
    case MessageType::kHeartbeat: return decode_into<Heartbeat>(r, out);
    case MessageType::kBye: return decode_into<Bye>(r, out);
  }
  return DecodeError::kUnknownType;
}

}  // namespace dhr
