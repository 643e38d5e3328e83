// The DHR wire protocol: message structs and their explicit little-endian encoding (docs/protocol.md
// has the byte layout, the handshake and what a receiver does with a datagram that fails validation).
// One message per UDP datagram; every datagram starts with the same 20-byte header. Each message's wire
// fields are listed once, in protocol/wire_layout.hpp, which also defines the size constants
// (kHeaderSize, kViewWireSize, kShardFixedSize, kMaxShardPayload, kMaxDatagramSize ...) and MessageType.
#pragma once
#include "math/pose.hpp"
#include "math/projection.hpp"
#include "math/trs.hpp"
#include "protocol/protocol_error.hpp"
#include "protocol/wire_layout.hpp"
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

#include <array>
#include <optional>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace dhr {

inline constexpr std::array<uint8_t, 4> kProtocolMagic = {'D', 'H', 'R', 'X'};
// 2: codec v2 capability, acknowledgements in PoseUpdate; 3: the header's flags (authentication,
// secure/envelope.hpp), shard payloads leave room for the seal's tag, Bye reasons 8 and 9; 4: the soft-levels
// capability and Welcome's soft light count (masks with Gray-coded level fields, visibility/visibility_layout.hpp);
// 5: scene time (DESIGN 5b) in PoseUpdate (the scene time of the pose's display) and VisibilityShard (the scene
// time the eye was traced for); 6: NodeTransform (app-moved nodes, docs/motion.md); 7: codec v2's mode and inter
// pixel contexts (codec/codec_v2.hpp: the same payload layout, other coded bits).
inline constexpr uint8_t kProtocolVersion = 7;

static_assert(kMaxShardPayload <= 1200);
// |q|^2 of a decoded quaternion must be within this of 1 (float rounding is ~1e-7); then renormalized.
inline constexpr double kQuaternionNormTolerance = 1e-3;

enum class Eye : uint8_t { kLeft = 0, kRight = 1 };

enum class ByeReason : uint8_t {
  kNormal = 0,           // the sender is done
  kTimeout = 1,          // no datagram from the peer within the session timeout
  kProtocolError = 2,    // the peer kept sending invalid datagrams
  kShutdown = 3,         // the server is shutting down
  kVersionMismatch = 4,  // the Hello spoke another protocol version
  kUnknownSession = 5,   // the token is not (or no longer) known: the client must send Hello again
  kBadHello = 6,         // Hello parameters unacceptable (size, lights, capabilities)
  kUnknownScene = 7,     // the requested scene id is not available
  kAuthRequired = 8,     // the server only takes authenticated datagrams: the client has no key
  kAuthFailed = 9,       // the Hello's tag did not verify: the client holds another key
};
inline constexpr uint8_t kMaxByeReason = 9;

// Capability bits (Hello: what the client supports; Welcome: what the server will use).
inline constexpr uint32_t kCapabilityLz4RowShards = 1u << 0;  // codec v1: LZ4 chunk shards (always supported)
inline constexpr uint32_t kCapabilityCodecV2 = 1u << 1;       // codec v2 (codec/codec_v2.hpp), intra and inter
// Soft levels: a light with an extent takes kSoftLevelBits bits (the Gray code of its visibility quantized to 8
// levels) instead of one, as VisibilityLayout::for_lights says; both ends derive the layout from the scene's
// lights. The server grants it only when the client offered it and the scene has such a light.
inline constexpr uint32_t kCapabilitySoftLevels = 1u << 2;
// Light slots: the scene has more than 32 lights, which share the mask's fields (scene/light_slots.hpp; field f is
// the light slot f holds where the pixel's surface is). Both ends derive the slots from the scene's lights, so
// nothing else travels: Welcome::light_count counts fields. A server whose scene needs them refuses a Hello
// without the bit (kBadHello); a client refuses a Welcome that grants them to a scene that has none, or not.
inline constexpr uint32_t kCapabilityLightSlots = 1u << 3;

struct Hello {
  uint64_t client_nonce = 0;  // random per attempt; Welcome echoes it
  uint32_t capabilities = kCapabilityLz4RowShards;
  uint16_t eye_width = 0;   // displayed size per eye, without guard band
  uint16_t eye_height = 0;
  uint16_t guard_x = 0;  // guard band per side, pixels: traced width = eye_width + 2 * guard_x
  uint16_t guard_y = 0;
  uint8_t light_count_wanted = 0;  // at most this many lights (1..32); 0 = as many as the scene has, up to 32
  std::string scene_id;            // <= kMaxSceneIdLength bytes, no control characters; empty = default
  TracedFormat format() const { return TracedFormat{Extent{eye_width, eye_height}, GuardBand{guard_x, guard_y}}; }
  bool operator==(const Hello&) const = default;
};

struct Welcome {
  uint64_t client_nonce = 0;  // echo of the Hello being answered
  uint32_t capabilities = kCapabilityLz4RowShards;
  uint64_t scene_hash = 0;   // identifies the scene content the server traces
  uint8_t light_count = 0;   // lights in every mask (0..32)
  MaskWidth mask_bits = MaskWidth::k8;  // must equal mask_width_for_light_count(used_mask_bits())
  // Lights given a level field (kSoftLevelBits bits) by the soft-levels capability; 0 without it. A check on
  // the layout the client derives from the scene (VisibilityLayout::for_lights), not the layout itself.
  uint8_t soft_light_count = 0;
  uint16_t buffer_width = 0;   // traced size per eye, guard band included
  uint16_t buffer_height = 0;
  uint16_t guard_x = 0;  // guard band per side actually used
  uint16_t guard_y = 0;
  uint16_t heartbeat_interval_ms = 1000;
  uint32_t session_timeout_ms = 5000;
  // Bits every mask uses: one per light, kSoftLevelBits per soft light (VisibilityLayout::total_bits()).
  uint32_t used_mask_bits() const { return uint32_t{light_count} + uint32_t{soft_light_count} * (kSoftLevelBits - 1); }
  // The granted format: the buffer minus the guard band on both sides is the displayed size.
  TracedFormat format() const {
    const auto display = [](uint32_t buffer, uint32_t guard) { return buffer > 2 * guard ? buffer - 2 * guard : 0u; };
    return TracedFormat{Extent{display(buffer_width, guard_x), display(buffer_height, guard_y)}, GuardBand{guard_x, guard_y}};
  }
  bool operator==(const Welcome&) const = default;
};

// A frame's pose on the wire (frame number, predicted display time on the client clock, XrTime, >= 0, the scene
// time of that display, >= 0, and both eyes' views, [Eye::kLeft], [Eye::kRight]: the FramePose the client's frame
// loop uses), plus the client's
// acknowledgements for codec v2: per eye, the newest complete frame it holds as a reference.
struct PoseUpdate : FramePose {
  // frame - held frame, per eye; 0: nothing held (or held frames more than 65535 frames old).
  std::array<uint16_t, 2> held_distance{};

  std::optional<uint64_t> held_frame(size_t eye) const {
    if (eye > 1 || held_distance[eye] == 0 || held_distance[eye] > frame) return std::nullopt;
    return frame - held_distance[eye];
  }
};

struct VisibilityShard {
  uint64_t frame_number = 0;  // the client frame whose pose was traced
  Eye eye = Eye::kLeft;
  MaskWidth mask_bits = MaskWidth::k8;
  uint16_t shard_index = 0;  // < shard_count
  uint16_t shard_count = 1;  // shards of this (frame, eye)
  uint16_t buffer_width = 0;
  uint16_t buffer_height = 0;
  uint32_t first_pixel = 0;  // region: pixels [first_pixel, first_pixel + pixel_count), row-major
  uint32_t pixel_count = 0;
  int64_t scene_time_ns = 0;  // the scene time this eye was traced for (ns since the session's start, >= 0)
  View view;                 // the view this eye was traced for (every shard carries it)
  uint16_t payload_size = 0;  // 1..kMaxShardPayload
  std::array<uint8_t, kMaxShardPayload> payload{};  // codec chunks (codec/codec.hpp)

  std::span<const uint8_t> payload_bytes() const { return std::span(payload).first(payload_size); }
};

struct Heartbeat {
  int64_t send_time_ns = 0;   // sender's clock when sent
  int64_t echo_time_ns = 0;   // send_time_ns of the newest Heartbeat received from the peer, 0 = none yet
  int64_t echo_delay_ns = 0;  // time between receiving that Heartbeat and sending this one
  uint64_t newest_frame = 0;  // client: newest complete visibility frame; server: newest frame traced
  uint32_t datagrams_sent = 0;
  uint32_t datagrams_received = 0;
  uint32_t datagrams_rejected = 0;
  uint32_t frames_done = 0;     // client: frames completed; server: frames traced and sent
  uint32_t frames_dropped = 0;  // client: frames evicted incomplete; server: poses skipped
  bool operator==(const Heartbeat&) const = default;
};

struct Bye {
  ByeReason reason = ByeReason::kNormal;
  bool operator==(const Bye&) const = default;
};

// An application moved glTF node `node`: from scene_time_ns on, its local transform is `trs` (replacing its
// animation or rest; the server extrapolates beyond the newest, scene/node_overrides.hpp). Decoding checks that it
// is finite, the stamp >= 0, the rotation unit within kQuaternionNormTolerance (then renormalized), every scale > 0
// and |translation| <= kMaxPositionMetres; which nodes may move is the receiver's to decide.
struct NodeTransform {
  uint32_t node = 0;
  int64_t scene_time_ns = 0;
  Trs trs;
  bool operator==(const NodeTransform&) const = default;
};

// The variant's order is the MessageType order.
using Message = std::variant<Hello, Welcome, PoseUpdate, VisibilityShard, Heartbeat, Bye, NodeTransform>;

struct Datagram {
  uint64_t session_token = 0;  // 0 only in Hello (and in a Bye answering a Hello)
  uint32_t sequence = 0;       // per-sender datagram counter, for loss statistics
  Message message;
};

struct DatagramHeader {
  uint8_t version = 0;
  MessageType type = MessageType::kHello;
  uint64_t session_token = 0;
  uint32_t sequence = 0;
};

MessageType message_type(const Message& message);
const char* to_string(MessageType type);
const char* to_string(ByeReason reason);

// Exact encoded size of a message (header included).
size_t encoded_size(const Message& message);

// Writes the datagram into `out`; returns the byte count, or 0 when `out` is too small or the message
// cannot be represented (scene id too long, payload_size above kMaxShardPayload). Values are not
// validated here: the receiver validates.
size_t encode_datagram(const Datagram& datagram, std::span<uint8_t> out);
std::vector<uint8_t> encode_datagram(const Datagram& datagram);  // empty on failure

// Validates size bounds, magic, version, type and the reserved field. On kWrongVersion, out.version
// holds the peer's version (for a helpful log line).
DecodeError decode_header(std::span<const uint8_t> bytes, DatagramHeader& out);

// Full decode and validation of one datagram. Never throws on any input; on error `out` is unspecified.
// Poses are validated (finite, unit quaternion within tolerance, position range) and renormalized.
DecodeError decode_datagram(std::span<const uint8_t> bytes, Datagram& out);

// The view exactly as a receiver decodes `view` from a message that carries it (orientation rounded to the
// wire's f32 and renormalized, as decode_datagram does); std::nullopt when no receiver would accept it. A
// sender that traces for a view it computed itself (a predicted one) traces this one and sends `view`: the
// receiver then holds the very view the bits were traced for. Not idempotent in general (the rounding of a
// renormalized quaternion need not give back the same floats), so round-trip the view that is sent, once.
std::optional<View> view_as_decoded(const View& view);

// The transform exactly as a receiver decodes `transform` (translation as sent, rotation and scale rounded to the
// wire's f32, the rotation renormalized); std::nullopt when no receiver would accept it. A sender that also applies
// the transform itself (the client's own rendering) records this one: both ends then hold the same bits.
std::optional<NodeTransform> node_transform_as_decoded(const NodeTransform& transform);

// Fuzz-friendly entry point, same as decode_datagram.
inline DecodeError decode_datagram(const uint8_t* data, size_t size, Datagram& out) {
  return decode_datagram(std::span<const uint8_t>(data, size), out);
}

}  // namespace dhr
