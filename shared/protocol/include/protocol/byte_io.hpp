// Explicit little-endian serialization for the wire format. Every field is written byte by byte
// (never a memcpy of a struct), so the layout does not depend on the compiler, padding or host order.
// Both classes are bounded by the span they wrap and never throw: a write past the end or a read past
// the end sets a sticky failure flag, so a decoder can read all fields and check ok() once.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

namespace dhr {

class ByteWriter {
 public:
  explicit ByteWriter(std::span<uint8_t> out) : out_(out) {}

  void u8(uint8_t v);
  void u16(uint16_t v);
  void u32(uint32_t v);
  void u64(uint64_t v);
  void i64(int64_t v) { u64(static_cast<uint64_t>(v)); }
  void f32(float v);   // IEEE-754 binary32 bit pattern, little-endian
  void f64(double v);  // IEEE-754 binary64 bit pattern, little-endian
  void bytes(std::span<const uint8_t> v);

  bool ok() const { return !failed_; }
  size_t size() const { return pos_; }  // bytes written so far (stops growing after a failure)
  std::span<uint8_t> written() const { return out_.first(pos_); }

 private:
  bool reserve(size_t n);
  std::span<uint8_t> out_;
  size_t pos_ = 0;
  bool failed_ = false;
};

class ByteReader {
 public:
  explicit ByteReader(std::span<const uint8_t> in) : in_(in) {}

  // Each read returns 0 (or an empty span) and sets the failure flag when too few bytes remain.
  uint8_t u8();
  uint16_t u16();
  uint32_t u32();
  uint64_t u64();
  int64_t i64() { return static_cast<int64_t>(u64()); }
  float f32();
  double f64();
  std::span<const uint8_t> bytes(size_t n);

  bool ok() const { return !failed_; }
  size_t position() const { return pos_; }
  size_t remaining() const { return in_.size() - pos_; }
  bool at_end() const { return pos_ == in_.size(); }

 private:
  bool take(size_t n);
  std::span<const uint8_t> in_;
  size_t pos_ = 0;
  bool failed_ = false;
};

}  // namespace dhr
