// The DHR wire format, each part listed once: the datagram header, the View, and every message grouped by
// direction. Encoding and decoding (src/wire_codec.hpp), the size constants below and protocol_layout()
// derive from these lists; docs/protocol.md's byte tables and tools/wireshark/dhr.lua's layout tables are
// checked against them (ProtocolLayout tests). Adding a field: its member in the struct (protocol.hpp), one
// line here, its row in docs/protocol.md, `dhr-protocol-layout --update-wireshark tools/wireshark/dhr.lua`,
// and a new kProtocolVersion.
//
// Order of a message's checks when decoding (it decides which DecodeError a malformed datagram gets):
// the fixed fields (kTruncated), the tail (its length, its bytes, its text), the message's validate()
// (ranges and cross-field rules, src/message_checks.cpp), then each View in list order.
#pragma once
#include "protocol/wire_fields.hpp"

#include <cstddef>
#include <cstdint>

namespace dhr {

// Largest datagram either side sends or accepts: fits the IPv6 minimum MTU path with room to spare
// over Ethernet (1280 + 8 UDP + 20 IPv4 < 1500), so no IP fragmentation.
inline constexpr size_t kMaxDatagramSize = 1280;
// A sealed datagram (secure/envelope.hpp) carries a 16-byte tag: every message leaves room for it.
inline constexpr size_t kSealOverhead = 16;
inline constexpr size_t kMaxPlainDatagramSize = kMaxDatagramSize - kSealOverhead;  // 1264
inline constexpr size_t kMaxSceneIdLength = 128;

enum class MessageType : uint8_t {
  kHello = 1,            // client -> server, token 0
  kWelcome = 2,          // server -> client, carries the new token
  kPoseUpdate = 3,       // client -> server, every frame
  kVisibilityShard = 4,  // server -> client, many per traced eye
  kHeartbeat = 5,        // both ways, ~1 Hz: liveness, clock-offset samples, counters
  kBye = 6,              // either way: session ends
  kNodeTransform = 7,    // client -> server: an application moved a node (from a scene time on)
};

struct Hello;
struct Welcome;
struct PoseUpdate;
struct VisibilityShard;
struct Heartbeat;
struct Bye;
struct NodeTransform;

namespace wire {
using enum WireType;
using enum Direction;

// Every datagram starts with it. Bytes 0-4 (magic, version) keep their meaning in every version.
inline constexpr auto kHeaderFields = std::tuple{
    field<kU8, 4>(DHR_WIRE_MEMBER(magic), "'D' 'H' 'R' 'X'"),
    field<kU8>(DHR_WIRE_MEMBER(version), "kProtocolVersion"),
    field<kU8>(DHR_WIRE_MEMBER(type), "MessageType"),
    field<kU16>(DHR_WIRE_MEMBER(flags), "0 plain; 1 sealed, 2 handshake tag (secure/envelope.hpp); decoded if 0"),
    field<kU64>(DHR_WIRE_MEMBER(session_token), "0 in Hello (and in a Bye answering a Hello), else non-zero"),
    field<kU32>(DHR_WIRE_MEMBER(sequence), "per-sender datagram counter, for loss statistics"),
};

// A quaternion's component i in the wire's x, y, z, w order (glm keeps w apart).
template <typename Quaternion>
constexpr auto& quaternion_xyzw(Quaternion& q, size_t i) {
  return i == 0 ? q.x : i == 1 ? q.y : i == 2 ? q.z : q.w;
}

// An eye's view, inside PoseUpdate and VisibilityShard.
inline constexpr auto kViewFields = std::tuple{
    field<kF64, 3>("position", [](auto& v, size_t i) -> auto& { return v.pose.position[static_cast<int>(i)]; },
                   "x, y, z, metres, world (f64: large world coordinates stay exact)"),
    field<kF32, 4>("orientation",
                   [](auto& v, size_t i) -> auto& { return quaternion_xyzw(v.pose.orientation, i); },
                   "quaternion x, y, z, w (OpenXR order; f32 is ~1e-7 rad, far below a pixel)"),
    field<kF32, 4>("fov",
                   [](auto& v, size_t i) -> auto& {
                     auto& f = v.fov;
                     return i == 0 ? f.angle_left : i == 1 ? f.angle_right : i == 2 ? f.angle_up : f.angle_down;
                   },
                   "angle_left, angle_right, angle_up, angle_down, radians (XrFovf)"),
};

constexpr auto view_field(std::string_view name, auto access, std::string_view doc) {
  return nested(name, access, "View", kViewFields, doc);
}

// ---- client -> server --------------------------------------------------------------------------------

inline constexpr auto kHelloLayout = message<Hello>(
    MessageType::kHello, "Hello", kClientToServer,
    std::tuple{
        field<kU64>(DHR_WIRE_MEMBER(client_nonce), "random per attempt, echoed by Welcome"),
        field<kU32>(DHR_WIRE_MEMBER(capabilities), "kCapability* bits the client supports"),
        field<kU16>(DHR_WIRE_MEMBER(eye_width), "displayed width per eye, without guard band"),
        field<kU16>(DHR_WIRE_MEMBER(eye_height), "displayed height per eye"),
        field<kU16>(DHR_WIRE_MEMBER(guard_x), "guard band per side, x: traced width = eye_width + 2 guard_x"),
        field<kU16>(DHR_WIRE_MEMBER(guard_y), "guard band per side, y"),
        field<kU8>(DHR_WIRE_MEMBER(light_count_wanted), "1..32; 0 = as many as the scene has, up to 32"),
        tail_length<kU8>("scene_id_length", "scene id length n"),
        text_tail(DHR_WIRE_MEMBER(scene_id), "n", kMaxSceneIdLength,
                  "no control characters; empty = the server's default scene"),
    });

inline constexpr auto kPoseUpdateLayout = message<PoseUpdate>(
    MessageType::kPoseUpdate, "PoseUpdate", kClientToServer,
    std::tuple{
        field<kU64>(DHR_WIRE_MEMBER(frame), "client frame number, increasing"),
        field<kI64>(DHR_WIRE_MEMBER(display_time_ns), "predicted display time, client clock (XrTime, >= 0)"),
        field<kI64>(DHR_WIRE_MEMBER(scene_time_ns), "scene time of that display, ns since the session's start, >= 0"),
        view_field("left_view", [](auto& m) -> auto& { return m.views[0]; }, "left eye"),
        view_field("right_view", [](auto& m) -> auto& { return m.views[1]; }, "right eye"),
        field<kU16, 2>(DHR_WIRE_MEMBER(held_distance),
                       "per eye: frame minus the newest complete frame held as a codec v2 reference; 0 = none"),
    });

inline constexpr auto kNodeTransformLayout = message<NodeTransform>(
    MessageType::kNodeTransform, "NodeTransform", kClientToServer,
    std::tuple{
        field<kU32>(DHR_WIRE_MEMBER(node), "glTF node index: one the scene lets an application move"),
        field<kI64>(DHR_WIRE_MEMBER(scene_time_ns), "scene time the transform holds from, ns since the session's start, >= 0"),
        field<kF64, 3>("translation", [](auto& m, size_t i) -> auto& { return m.trs.translation[static_cast<int>(i)]; },
                       "x, y, z, metres, in the parent's frame (the node's local glTF translation)"),
        field<kF32, 4>("rotation",
                       [](auto& m, size_t i) -> auto& { return quaternion_xyzw(m.trs.rotation, i); },
                       "local rotation quaternion x, y, z, w (glTF order), unit within tolerance"),
        field<kF32, 3>("scale", [](auto& m, size_t i) -> auto& { return m.trs.scale[static_cast<int>(i)]; },
                       "local scale x, y, z, each > 0"),
    });

// ---- server -> client --------------------------------------------------------------------------------

inline constexpr auto kWelcomeLayout = message<Welcome>(
    MessageType::kWelcome, "Welcome", kServerToClient,
    std::tuple{
        field<kU64>(DHR_WIRE_MEMBER(client_nonce), "echo of the Hello answered"),
        field<kU32>(DHR_WIRE_MEMBER(capabilities), "kCapability* bits the server will use"),
        field<kU64>(DHR_WIRE_MEMBER(scene_hash), "identifies the traced scene content"),
        field<kU8>(DHR_WIRE_MEMBER(light_count), "fields in every mask, 0..32: lights, or the slots they share"),
        field<kU8>(DHR_WIRE_MEMBER(mask_bits), "8, 16 or 32: holds light_count + 2 soft_light_count bits"),
        field<kU8>(DHR_WIRE_MEMBER(soft_light_count), "lights with a 3-bit level field; 0 without soft levels"),
        field<kU16>(DHR_WIRE_MEMBER(buffer_width), "traced width per eye, guard band included"),
        field<kU16>(DHR_WIRE_MEMBER(buffer_height), "traced height per eye"),
        field<kU16>(DHR_WIRE_MEMBER(guard_x), "guard band per side actually used, x"),
        field<kU16>(DHR_WIRE_MEMBER(guard_y), "guard band per side actually used, y"),
        field<kU16>(DHR_WIRE_MEMBER(heartbeat_interval_ms), "heartbeat interval, >= 1"),
        field<kU32>(DHR_WIRE_MEMBER(session_timeout_ms), "session timeout, >= 1"),
    });

inline constexpr auto kVisibilityShardLayout = message<VisibilityShard>(
    MessageType::kVisibilityShard, "VisibilityShard", kServerToClient,
    std::tuple{
        field<kU64>(DHR_WIRE_MEMBER(frame_number), "the client frame whose pose was traced"),
        field<kU8>(DHR_WIRE_MEMBER(eye), "0 left, 1 right"),
        field<kU8>(DHR_WIRE_MEMBER(mask_bits), "8, 16 or 32"),
        field<kU16>(DHR_WIRE_MEMBER(shard_index), "< shard_count"),
        field<kU16>(DHR_WIRE_MEMBER(shard_count), "shards of this (frame, eye), >= 1"),
        field<kU16>(DHR_WIRE_MEMBER(buffer_width), "1..4096, the session's"),
        field<kU16>(DHR_WIRE_MEMBER(buffer_height), "1..4096, the session's"),
        tail_length<kU16>(DHR_WIRE_MEMBER(payload_size), "payload size p, 1..kMaxShardPayload"),
        field<kU32>(DHR_WIRE_MEMBER(first_pixel), "region start, row-major pixel index"),
        field<kU32>(DHR_WIRE_MEMBER(pixel_count), "region length, >= 1, within the buffer"),
        field<kI64>(DHR_WIRE_MEMBER(scene_time_ns), "scene time the eye was traced for, ns, >= 0"),
        view_field(DHR_WIRE_MEMBER(view), "the view this eye was traced for"),
        bytes_tail(DHR_WIRE_MEMBER(payload), "p", 1, kRestOfDatagram, "codec chunks (codec/codec.hpp)"),
    });

// ---- both ways ---------------------------------------------------------------------------------------

inline constexpr auto kHeartbeatLayout = message<Heartbeat>(
    MessageType::kHeartbeat, "Heartbeat", kBothWays,
    std::tuple{
        field<kI64>(DHR_WIRE_MEMBER(send_time_ns), "sender's clock when sent, >= 0"),
        field<kI64>(DHR_WIRE_MEMBER(echo_time_ns), "send time of the newest Heartbeat received, 0 = none yet"),
        field<kI64>(DHR_WIRE_MEMBER(echo_delay_ns), "time from receiving that Heartbeat to sending this one, >= 0"),
        field<kU64>(DHR_WIRE_MEMBER(newest_frame), "client: newest complete frame; server: newest frame traced"),
        field<kU32>(DHR_WIRE_MEMBER(datagrams_sent), "sender's counter"),
        field<kU32>(DHR_WIRE_MEMBER(datagrams_received), "sender's counter"),
        field<kU32>(DHR_WIRE_MEMBER(datagrams_rejected), "sender's counter"),
        field<kU32>(DHR_WIRE_MEMBER(frames_done), "client: frames completed; server: frames traced and sent"),
        field<kU32>(DHR_WIRE_MEMBER(frames_dropped), "client: frames evicted incomplete; server: poses skipped"),
    });

inline constexpr auto kByeLayout = message<Bye>(
    MessageType::kBye, "Bye", kBothWays,
    std::tuple{
        field<kU8>(DHR_WIRE_MEMBER(reason), "ByeReason"),
    });

// Every message, grouped by direction as above.
inline constexpr auto kMessageLayouts = std::tuple{kHelloLayout,     kPoseUpdateLayout,      kNodeTransformLayout,
                                                   kWelcomeLayout,   kVisibilityShardLayout, kHeartbeatLayout,
                                                   kByeLayout};

inline constexpr size_t kHeaderBytes = fixed_size<decltype(kHeaderFields)>();

// The largest tail a message may carry: its own limit, or what is left of a plain datagram.
template <class Layout>
constexpr size_t tail_max_length(const Layout& layout) {
  const auto& tail = last_field(layout.fields);
  return tail.max_length != kRestOfDatagram ? tail.max_length
                                            : kMaxPlainDatagramSize - kHeaderBytes - Layout::kFixedBodySize;
}

}  // namespace wire

inline constexpr size_t kHeaderSize = wire::kHeaderBytes;
inline constexpr size_t kViewWireSize = wire::fixed_size<decltype(wire::kViewFields)>();
// A shard's datagram without its payload; the payload takes the rest of a plain datagram.
inline constexpr size_t kShardFixedSize = kHeaderSize + wire::kVisibilityShardLayout.kFixedBodySize;
inline constexpr size_t kMaxShardPayload = wire::tail_max_length(wire::kVisibilityShardLayout);

}  // namespace dhr
