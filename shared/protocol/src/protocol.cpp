#include "protocol/protocol.hpp"

#include "wire_codec.hpp"

#include <utility>

namespace dhr {
namespace {

using wire::kHeaderFields;
using wire::WireHeader;

static_assert(std::get<0>(kHeaderFields).name == "magic" && std::get<1>(kHeaderFields).name == "version",
              "decode_header reads the magic and the version first: they mean the same in every version");
static_assert(std::get<2>(kHeaderFields).name == "type");

// The Message variant's order is the type ids' order.
static_assert([]<size_t... I>(std::index_sequence<I...>) {
  return ((wire::layout_of<std::variant_alternative_t<I, Message>>().type == static_cast<MessageType>(I + 1)) && ...);
}(std::make_index_sequence<std::variant_size_v<Message>>{}));

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
    case MessageType::kNodeTransform: return "NodeTransform";
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
  return kHeaderSize + std::visit([](const auto& m) { return wire::body_size(m); }, message);
}

size_t encode_datagram(const Datagram& datagram, std::span<uint8_t> out) {
  const bool ok = std::visit([](const auto& m) { return wire::representable(m); }, datagram.message);
  const size_t size = encoded_size(datagram.message);
  if (!ok || size > out.size()) return 0;
  ByteWriter w(out);
  const WireHeader header{kProtocolMagic, kProtocolVersion, static_cast<uint8_t>(message_type(datagram.message)), 0,
                          datagram.session_token, datagram.sequence};
  wire::write_fields(w, kHeaderFields, header);
  std::visit([&w](const auto& m) { wire::write_fields(w, wire::layout_of<std::decay_t<decltype(m)>>().fields, m); },
             datagram.message);
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
  WireHeader h;
  size_t unused = 0;
  // The magic, then the version: checked before the rest so a peer of another version is recognised even
  // if the rest of its header differs.
  wire::read_fields(r, std::tuple{std::get<0>(kHeaderFields)}, h, unused);
  if (!r.ok()) return DecodeError::kTruncated;
  if (h.magic != kProtocolMagic) return DecodeError::kBadMagic;
  wire::read_fields(r, std::tuple{std::get<1>(kHeaderFields)}, h, unused);
  if (!r.ok()) return DecodeError::kTruncated;
  out.version = h.version;
  if (h.version != kProtocolVersion) return DecodeError::kWrongVersion;
  wire::read_fields(r, wire::drop_first<2>(kHeaderFields), h, unused);
  if (!r.ok()) return DecodeError::kTruncated;
  out.session_token = h.session_token;
  out.sequence = h.sequence;
  if (h.type < static_cast<uint8_t>(MessageType::kHello) || h.type > static_cast<uint8_t>(MessageType::kNodeTransform))
    return DecodeError::kUnknownType;
  out.type = static_cast<MessageType>(h.type);
  if (h.flags != 0) return DecodeError::kBadReserved;  // sealed and tagged datagrams are opened before decoding
  if (!token_ok(out.type, out.session_token)) return DecodeError::kBadToken;
  return DecodeError::kNone;
}

namespace {
template <class T>
DecodeError decode_into(ByteReader& r, Datagram& out) {
  T& m = out.message.emplace<T>();
  const DecodeError e = wire::read_body(r, m);
  if (e != DecodeError::kNone) return e;
  return r.at_end() ? DecodeError::kNone : DecodeError::kTrailingBytes;
}

template <size_t I = 0>
DecodeError decode_body(MessageType type, ByteReader& r, Datagram& out) {
  if constexpr (I == std::variant_size_v<Message>) {
    return DecodeError::kUnknownType;
  } else {
    using T = std::variant_alternative_t<I, Message>;
    return wire::layout_of<T>().type == type ? decode_into<T>(r, out) : decode_body<I + 1>(type, r, out);
  }
}
}  // namespace

DecodeError decode_datagram(std::span<const uint8_t> bytes, Datagram& out) {
  DatagramHeader header;
  if (const DecodeError e = decode_header(bytes, header); e != DecodeError::kNone) return e;
  out.session_token = header.session_token;
  out.sequence = header.sequence;
  ByteReader r(bytes.subspan(kHeaderSize));
  return decode_body(header.type, r, out);
}

std::optional<View> view_as_decoded(const View& view) {
  std::array<uint8_t, kViewWireSize> bytes{};
  ByteWriter w(bytes);
  wire::write_fields(w, wire::kViewFields, view);
  ByteReader r(bytes);
  View out;
  size_t unused = 0;
  wire::read_fields(r, wire::kViewFields, out, unused);
  if (!w.ok() || !r.ok() || wire::check_nested(out) != DecodeError::kNone) return std::nullopt;
  return out;
}

std::optional<NodeTransform> node_transform_as_decoded(const NodeTransform& transform) {
  // Through the codec itself (any token: only the message matters), so the result is what a receiver holds.
  const std::vector<uint8_t> bytes = encode_datagram(Datagram{1, 0, transform});
  Datagram out;
  if (bytes.empty() || decode_datagram(bytes, out) != DecodeError::kNone) return std::nullopt;
  return std::get<NodeTransform>(out.message);
}

}  // namespace dhr
