// Building blocks of the wire layout lists (protocol/wire_layout.hpp). A field names its wire type and how
// to reach its value in the message; encoding, decoding, the sizes and the layout description
// (protocol/protocol_layout.hpp) are all derived from one such list per message. Accessors are generic
// lambdas so that the lists can come before the message structs: VisibilityShard's payload array is sized
// by kMaxShardPayload, which derives from the shard's list.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>

namespace dhr {
enum class MessageType : uint8_t;  // protocol/wire_layout.hpp
}

namespace dhr::wire {

// Fixed-size wire types: unsigned and signed integers, IEEE-754 floats; all little-endian (byte_io.hpp).
enum class WireType : uint8_t { kU8, kU16, kU32, kU64, kI64, kF32, kF64 };

constexpr size_t wire_size(WireType type) {
  switch (type) {
    case WireType::kU8: return 1;
    case WireType::kU16: return 2;
    case WireType::kU32: case WireType::kF32: return 4;
    case WireType::kU64: case WireType::kI64: case WireType::kF64: return 8;
  }
  return 0;
}

constexpr std::string_view wire_name(WireType type) {
  switch (type) {
    case WireType::kU8: return "u8";
    case WireType::kU16: return "u16";
    case WireType::kU32: return "u32";
    case WireType::kU64: return "u64";
    case WireType::kI64: return "i64";
    case WireType::kF32: return "f32";
    case WireType::kF64: return "f64";
  }
  return "?";
}

// What a field is; the codec and the layout description switch on it.
enum class FieldKind : uint8_t { kScalar, kTailLength, kNested, kTail };

// Count values of type W. access(message) -> the member (a reference); an array (Count > 1) is either a
// member indexable with [] or access(message, i) -> element i. Encoding casts the member to the wire type,
// decoding casts back (enums travel as their underlying value, doubles as f32 where the list says so).
template <WireType W, size_t Count, class Access>
struct Scalar {
  static constexpr FieldKind kFieldKind = FieldKind::kScalar;
  static constexpr WireType kType = W;
  static constexpr size_t kCount = Count;
  static constexpr size_t kSize = Count * wire_size(W);
  std::string_view name;
  Access access;
  std::string_view doc;
};

// No struct member: the value exists on the wire only.
struct NoMember {};

// The length of the message's variable tail, in the fixed part. With a member (VisibilityShard's
// payload_size) it travels as the member's value; without one (Hello's scene id length) as the tail's size.
template <WireType W, class Access>
struct TailLength {
  static constexpr FieldKind kFieldKind = FieldKind::kTailLength;
  static constexpr WireType kType = W;
  static constexpr size_t kSize = wire_size(W);
  std::string_view name;
  Access access;
  std::string_view doc;
};

template <class Field>
constexpr size_t fixed_field_size() {
  if constexpr (Field::kFieldKind == FieldKind::kTail) {
    return 0;  // variable
  } else {
    return Field::kSize;
  }
}

// Bytes of the fixed part of a field list (everything but a tail).
template <class Fields>
constexpr size_t fixed_size() {
  return []<size_t... I>(std::index_sequence<I...>) {
    return (size_t{0} + ... + fixed_field_size<std::tuple_element_t<I, Fields>>());
  }(std::make_index_sequence<std::tuple_size_v<Fields>>{});
}

template <class Fields>
constexpr size_t count_kind(FieldKind kind) {
  return []<size_t... I>(FieldKind k, std::index_sequence<I...>) {
    return (size_t{0} + ... + (std::tuple_element_t<I, Fields>::kFieldKind == k ? 1 : 0));
  }(kind, std::make_index_sequence<std::tuple_size_v<Fields>>{});
}

template <class Fields>
inline constexpr bool kHasTail =
    std::tuple_element_t<std::tuple_size_v<Fields> - 1, Fields>::kFieldKind == FieldKind::kTail;

// At most one tail, last, with exactly one TailLength before it.
template <class Fields>
constexpr bool tail_well_placed() {
  const size_t tails = count_kind<Fields>(FieldKind::kTail);
  return tails == count_kind<Fields>(FieldKind::kTailLength) && tails == (kHasTail<Fields> ? 1 : 0);
}

// A block of fields inside a message (the View), read field-wise and then checked as a whole by the
// decoder's check_nested overload for its type.
template <class Fields, class Access>
struct Nested {
  static constexpr FieldKind kFieldKind = FieldKind::kNested;
  static constexpr size_t kSize = fixed_size<Fields>();
  std::string_view name;
  std::string_view type_name;  // how the layout table names it ("View")
  Fields fields;
  Access access;
  std::string_view doc;
};

// The variable part at the end of a message; its length travels in the message's TailLength field. Text:
// a std::string member (kBadString when too long or holding control characters). Bytes: a byte array member
// of which the first `length` bytes travel (kBadValue when the length is out of range).
enum class TailKind : uint8_t { kText, kBytes };
inline constexpr size_t kRestOfDatagram = std::numeric_limits<size_t>::max();  // up to kMaxPlainDatagramSize

template <TailKind K, class Access>
struct Tail {
  static constexpr FieldKind kFieldKind = FieldKind::kTail;
  static constexpr TailKind kKind = K;
  std::string_view name;
  Access access;
  std::string_view symbol;  // the length's name in the layout table: "u8[n]"
  size_t min_length;
  size_t max_length;  // or kRestOfDatagram
  std::string_view doc;
};

template <class Fields>
constexpr const auto& last_field(const Fields& fields) {
  return std::get<std::tuple_size_v<Fields> - 1>(fields);
}

// The list without its first N fields.
template <size_t N, class Fields>
constexpr auto drop_first(const Fields& fields) {
  return [&]<size_t... I>(std::index_sequence<I...>) {
    return std::tuple{std::get<N + I>(fields)...};
  }(std::make_index_sequence<std::tuple_size_v<Fields> - N>{});
}

// The list's TailLength field (call only on a list with a tail).
template <class Fields>
constexpr const auto& tail_length_field(const Fields& fields) {
  constexpr size_t index = []<size_t... I>(std::index_sequence<I...>) {
    size_t found = 0;
    ((found = std::tuple_element_t<I, Fields>::kFieldKind == FieldKind::kTailLength ? I : found), ...);
    return found;
  }(std::make_index_sequence<std::tuple_size_v<Fields>>{});
  return std::get<index>(fields);
}

enum class Direction : uint8_t { kClientToServer, kServerToClient, kBothWays };

constexpr std::string_view direction_name(Direction direction) {
  switch (direction) {
    case Direction::kClientToServer: return "client -> server";
    case Direction::kServerToClient: return "server -> client";
    case Direction::kBothWays: return "both ways";
  }
  return "?";
}

// One message: its type id, name, direction and fields (offsets follow the 20-byte header).
template <class M, class Fields>
struct MessageLayout {
  using Message = M;
  static constexpr size_t kFixedBodySize = fixed_size<Fields>();
  MessageType type;
  std::string_view name;
  Direction direction;
  Fields fields;
};

// ---- constructors used by the lists ------------------------------------------------------------------

template <WireType W, size_t Count = 1, class Access>
constexpr auto field(std::string_view name, Access access, std::string_view doc) {
  return Scalar<W, Count, Access>{name, access, doc};
}

template <WireType W>
constexpr auto tail_length(std::string_view name, std::string_view doc) {
  return TailLength<W, NoMember>{name, NoMember{}, doc};
}

template <WireType W, class Access>
constexpr auto tail_length(std::string_view name, Access access, std::string_view doc) {
  return TailLength<W, Access>{name, access, doc};
}

template <class Fields, class Access>
constexpr auto nested(std::string_view name, Access access, std::string_view type_name, const Fields& fields,
                      std::string_view doc) {
  static_assert(!kHasTail<Fields>, "a nested block has a fixed size");
  return Nested<Fields, Access>{name, type_name, fields, access, doc};
}

template <class Access>
constexpr auto text_tail(std::string_view name, Access access, std::string_view symbol, size_t max_length,
                         std::string_view doc) {
  return Tail<TailKind::kText, Access>{name, access, symbol, 0, max_length, doc};
}

template <class Access>
constexpr auto bytes_tail(std::string_view name, Access access, std::string_view symbol, size_t min_length,
                          size_t max_length, std::string_view doc) {
  return Tail<TailKind::kBytes, Access>{name, access, symbol, min_length, max_length, doc};
}

template <class M, class Fields>
constexpr auto message(MessageType type, std::string_view name, Direction direction, const Fields& fields) {
  static_assert(tail_well_placed<Fields>(), "a tail comes last, with one TailLength field before it");
  return MessageLayout<M, Fields>{type, name, direction, fields};
}

// The layout in `layouts` (a tuple of MessageLayout) whose struct is M.
template <class M, class Layouts>
constexpr const auto& layout_for(const Layouts& layouts) {
  constexpr size_t index = []<size_t... I>(std::index_sequence<I...>) {
    size_t found = sizeof...(I);
    ((found = std::is_same_v<typename std::tuple_element_t<I, Layouts>::Message, M> ? I : found), ...);
    return found;
  }(std::make_index_sequence<std::tuple_size_v<Layouts>>{});
  static_assert(index < std::tuple_size_v<Layouts>, "no layout lists this message struct");
  return std::get<index>(layouts);
}

}  // namespace dhr::wire

// A message member as a field's name and accessor: DHR_WIRE_MEMBER(guard_x) -> "guard_x", m.guard_x.
#define DHR_WIRE_MEMBER(member) #member, [](auto& m) -> auto& { return m.member; }
