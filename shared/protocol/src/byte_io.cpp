#include "protocol/byte_io.hpp"

#include <bit>

namespace dhr {

bool ByteWriter::reserve(size_t n) {
  if (failed_ || n > out_.size() - pos_) {
    failed_ = true;
    return false;
  }
  return true;
}

void ByteWriter::u8(uint8_t v) {
  if (!reserve(1)) return;
  out_[pos_++] = v;
}

void ByteWriter::u16(uint16_t v) {
  if (!reserve(2)) return;
  out_[pos_++] = static_cast<uint8_t>(v);
  out_[pos_++] = static_cast<uint8_t>(v >> 8);
}

void ByteWriter::u32(uint32_t v) {
  if (!reserve(4)) return;
  for (int i = 0; i < 4; ++i) out_[pos_++] = static_cast<uint8_t>(v >> (8 * i));
}

void ByteWriter::u64(uint64_t v) {
  if (!reserve(8)) return;
  for (int i = 0; i < 8; ++i) out_[pos_++] = static_cast<uint8_t>(v >> (8 * i));
}

void ByteWriter::f32(float v) { u32(std::bit_cast<uint32_t>(v)); }
void ByteWriter::f64(double v) { u64(std::bit_cast<uint64_t>(v)); }

void ByteWriter::bytes(std::span<const uint8_t> v) {
  if (!reserve(v.size())) return;
  for (uint8_t b : v) out_[pos_++] = b;
}

bool ByteReader::take(size_t n) {
  if (failed_ || n > in_.size() - pos_) {
    failed_ = true;
    return false;
  }
  return true;
}

uint8_t ByteReader::u8() {
  if (!take(1)) return 0;
  return in_[pos_++];
}

uint16_t ByteReader::u16() {
  if (!take(2)) return 0;
  const uint16_t v = static_cast<uint16_t>(in_[pos_] | (in_[pos_ + 1] << 8));
  pos_ += 2;
  return v;
}

uint32_t ByteReader::u32() {
  if (!take(4)) return 0;
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(in_[pos_++]) << (8 * i);
  return v;
}

uint64_t ByteReader::u64() {
  if (!take(8)) return 0;
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(in_[pos_++]) << (8 * i);
  return v;
}

float ByteReader::f32() { return std::bit_cast<float>(u32()); }
double ByteReader::f64() { return std::bit_cast<double>(u64()); }

std::span<const uint8_t> ByteReader::bytes(size_t n) {
  if (!take(n)) return {};
  const auto out = in_.subspan(pos_, n);
  pos_ += n;
  return out;
}

}  // namespace dhr
