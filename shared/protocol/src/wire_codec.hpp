// Field-wise encoding and decoding of the lists in protocol/wire_layout.hpp, through ByteWriter/ByteReader
// (explicit little-endian, never a memcpy of a struct). Internal to dhr_protocol.
#pragma once
#include "protocol/byte_io.hpp"
#include "protocol/protocol.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <type_traits>

namespace dhr::wire {

// The header as it travels (DatagramHeader is what decode_header reports).
struct WireHeader {
  std::array<uint8_t, 4> magic{};
  uint8_t version = 0;
  uint8_t type = 0;
  uint16_t flags = 0;
  uint64_t session_token = 0;
  uint32_t sequence = 0;
};

template <WireType W>
struct WireValueOf;
template <> struct WireValueOf<kU8> { using Type = uint8_t; };
template <> struct WireValueOf<kU16> { using Type = uint16_t; };
template <> struct WireValueOf<kU32> { using Type = uint32_t; };
template <> struct WireValueOf<kU64> { using Type = uint64_t; };
template <> struct WireValueOf<kI64> { using Type = int64_t; };
template <> struct WireValueOf<kF32> { using Type = float; };
template <> struct WireValueOf<kF64> { using Type = double; };
template <WireType W>
using WireValue = typename WireValueOf<W>::Type;

template <WireType W>
void put(ByteWriter& w, WireValue<W> v) {
  if constexpr (W == kU8) w.u8(v);
  else if constexpr (W == kU16) w.u16(v);
  else if constexpr (W == kU32) w.u32(v);
  else if constexpr (W == kU64) w.u64(v);
  else if constexpr (W == kI64) w.i64(v);
  else if constexpr (W == kF32) w.f32(v);
  else w.f64(v);
}

template <WireType W>
WireValue<W> get(ByteReader& r) {
  if constexpr (W == kU8) return r.u8();
  else if constexpr (W == kU16) return r.u16();
  else if constexpr (W == kU32) return r.u32();
  else if constexpr (W == kU64) return r.u64();
  else if constexpr (W == kI64) return r.i64();
  else if constexpr (W == kF32) return r.f32();
  else return r.f64();
}

// Element i of a Scalar field of m (a reference into m).
template <class F, class M>
decltype(auto) element(const F& f, M& m, size_t i) {
  if constexpr (F::kCount == 1) {
    return f.access(m);
  } else if constexpr (std::is_invocable_v<decltype(f.access), M&, size_t>) {
    return f.access(m, i);
  } else {
    return f.access(m)[i];
  }
}

// The tail's length in m as the encoder sends it (call only on a list with a tail).
template <class Fields, class M>
size_t tail_size(const Fields& fields, const M& m) {
  const auto& tail = last_field(fields);
  if constexpr (std::remove_cvref_t<decltype(tail)>::kKind == TailKind::kText) {
    return tail.access(m).size();
  } else {
    return tail_length_field(fields).access(m);
  }
}

template <class Fields, class M>
void write_fields(ByteWriter& w, const Fields& fields, const M& m);
template <class Fields, class M>
void read_fields(ByteReader& r, const Fields& fields, M& m, size_t& tail_bytes);

template <class F, class Fields, class M>
void write_field(ByteWriter& w, const F& f, const Fields& fields, const M& m) {
  if constexpr (F::kFieldKind == FieldKind::kScalar) {
    for (size_t i = 0; i < F::kCount; ++i) put<F::kType>(w, static_cast<WireValue<F::kType>>(element(f, m, i)));
  } else if constexpr (F::kFieldKind == FieldKind::kTailLength) {
    put<F::kType>(w, static_cast<WireValue<F::kType>>(tail_size(fields, m)));
  } else if constexpr (F::kFieldKind == FieldKind::kNested) {
    write_fields(w, f.fields, f.access(m));
  } else {
    const auto& data = f.access(m);
    w.bytes(std::span(reinterpret_cast<const uint8_t*>(data.data()), tail_size(fields, m)));
  }
}

template <class Fields, class M>
void write_fields(ByteWriter& w, const Fields& fields, const M& m) {
  std::apply([&](const auto&... f) { (write_field(w, f, fields, m), ...); }, fields);
}

template <class F, class M>
void read_field(ByteReader& r, const F& f, M& m, size_t& tail_bytes) {
  if constexpr (F::kFieldKind == FieldKind::kScalar) {
    for (size_t i = 0; i < F::kCount; ++i) {
      auto& target = element(f, m, i);
      target = static_cast<std::remove_reference_t<decltype(target)>>(get<F::kType>(r));
    }
  } else if constexpr (F::kFieldKind == FieldKind::kTailLength) {
    const auto value = get<F::kType>(r);
    tail_bytes = value;
    if constexpr (!std::is_same_v<std::remove_cvref_t<decltype(f.access)>, NoMember>) {
      auto& target = f.access(m);
      target = static_cast<std::remove_reference_t<decltype(target)>>(value);
    }
  } else if constexpr (F::kFieldKind == FieldKind::kNested) {
    size_t unused = 0;
    read_fields(r, f.fields, f.access(m), unused);
  }
  // The tail is read by read_tail, after the fixed part proved complete.
}

// Reads the fixed part; a TailLength lands in tail_bytes (and in its member, if it has one). The caller
// checks r.ok() once afterwards.
template <class Fields, class M>
void read_fields(ByteReader& r, const Fields& fields, M& m, size_t& tail_bytes) {
  std::apply([&](const auto&... f) { (read_field(r, f, m, tail_bytes), ...); }, fields);
}

inline bool is_control_character(uint8_t c) { return c < 0x20 || c == 0x7F; }

// The tail: its length against the limits, its bytes, its text. n is what the TailLength field said.
template <class Layout, class M>
DecodeError read_tail(ByteReader& r, const Layout& layout, M& m, size_t n) {
  const auto& tail = last_field(layout.fields);
  constexpr bool kText = std::remove_cvref_t<decltype(tail)>::kKind == TailKind::kText;
  const DecodeError bad_length = kText ? DecodeError::kBadString : DecodeError::kBadValue;
  if (n < tail.min_length || n > tail_max_length(layout)) return bad_length;
  const auto bytes = r.bytes(n);
  if (!r.ok()) return DecodeError::kTruncated;
  auto& data = tail.access(m);
  if constexpr (kText) {
    for (uint8_t c : bytes)
      if (is_control_character(c)) return DecodeError::kBadString;
    data.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  } else {
    for (size_t i = 0; i < bytes.size(); ++i) data[i] = bytes[i];
  }
  return DecodeError::kNone;
}

DecodeError check_nested(View& view);  // message_checks.cpp

template <class F, class M>
DecodeError check_one_nested(const F& f, M& m) {
  if constexpr (F::kFieldKind == FieldKind::kNested) {
    return check_nested(f.access(m));
  } else {
    return DecodeError::kNone;
  }
}

// Each nested block's own check (check_nested overloads), in list order.
template <class Fields, class M>
DecodeError check_nested_fields(const Fields& fields, M& m) {
  DecodeError error = DecodeError::kNone;
  std::apply(
      [&](const auto&... f) {
        (void)((error = check_one_nested(f, m), error == DecodeError::kNone) && ...);
      },
      fields);
  return error;
}

// Semantic checks after the field-wise read (message_checks.cpp).
DecodeError validate(const Hello& m);
DecodeError validate(const Welcome& m);
DecodeError validate(const PoseUpdate& m);
DecodeError validate(const VisibilityShard& m);
DecodeError validate(const Heartbeat& m);
DecodeError validate(const Bye& m);
DecodeError validate(NodeTransform& m);  // renormalizes the rotation

template <class M>
constexpr const auto& layout_of() {
  return layout_for<M>(kMessageLayouts);
}

// Encoded body size of m (the header not included).
template <class M>
size_t body_size(const M& m) {
  constexpr const auto& layout = layout_of<M>();
  if constexpr (kHasTail<decltype(layout.fields)>) {
    return layout.kFixedBodySize + tail_size(layout.fields, m);
  } else {
    return layout.kFixedBodySize;
  }
}

// Whether m fits its wire format (scene id, payload size within their limits).
template <class M>
bool representable(const M& m) {
  constexpr const auto& layout = layout_of<M>();
  if constexpr (kHasTail<decltype(layout.fields)>) {
    return tail_size(layout.fields, m) <= tail_max_length(layout);
  } else {
    return true;
  }
}

// Decodes a body in the order wire_layout.hpp states: fixed fields, tail, validate(), nested blocks.
template <class M>
DecodeError read_body(ByteReader& r, M& m) {
  constexpr const auto& layout = layout_of<M>();
  size_t n = 0;
  read_fields(r, layout.fields, m, n);
  if (!r.ok()) return DecodeError::kTruncated;
  if constexpr (kHasTail<decltype(layout.fields)>) {
    if (const DecodeError e = read_tail(r, layout, m, n); e != DecodeError::kNone) return e;
  }
  if (const DecodeError e = validate(m); e != DecodeError::kNone) return e;
  return check_nested_fields(layout.fields, m);
}

}  // namespace dhr::wire
