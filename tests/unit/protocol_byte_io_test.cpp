#include "protocol/byte_io.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace dhr {
namespace {

TEST(ByteIo, WritesLittleEndian) {
  std::array<uint8_t, 27> buf{};
  ByteWriter w(buf);
  w.u8(0xAB);
  w.u16(0x1234);
  w.u32(0xDEADBEEF);
  w.u64(0x0102030405060708ull);
  w.f32(1.0f);
  w.f64(-2.0);
  ASSERT_TRUE(w.ok());
  ASSERT_EQ(w.size(), 27u);
  const std::array<uint8_t, 27> expected = {0xAB, 0x34, 0x12, 0xEF, 0xBE, 0xAD, 0xDE, 0x08, 0x07,
                                            0x06, 0x05, 0x04, 0x03, 0x02, 0x01, 0x00, 0x00, 0x80,
                                            0x3F, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xC0};
  EXPECT_EQ(buf, expected);
}

TEST(ByteIo, ReadsBackWhatWasWritten) {
  std::vector<uint8_t> buf(64);
  ByteWriter w(buf);
  w.u8(7);
  w.u16(65535);
  w.u32(0x80000001u);
  w.u64(UINT64_MAX);
  w.i64(-5);
  w.f32(-0.0f);
  w.f64(std::numeric_limits<double>::infinity());
  ByteReader r(w.written());
  EXPECT_EQ(r.u8(), 7);
  EXPECT_EQ(r.u16(), 65535);
  EXPECT_EQ(r.u32(), 0x80000001u);
  EXPECT_EQ(r.u64(), UINT64_MAX);
  EXPECT_EQ(r.i64(), -5);
  const float nz = r.f32();
  EXPECT_TRUE(nz == 0.0f && std::signbit(nz));
  EXPECT_TRUE(std::isinf(r.f64()));
  EXPECT_TRUE(r.ok());
  EXPECT_TRUE(r.at_end());
}

TEST(ByteIo, WriterStopsAtTheEndAndStaysFailed) {
  std::array<uint8_t, 5> buf{};
  ByteWriter w(buf);
  w.u32(1);
  EXPECT_TRUE(w.ok());
  w.u16(2);  // needs 2, has 1
  EXPECT_FALSE(w.ok());
  w.u8(3);  // would fit, but the writer has failed
  EXPECT_FALSE(w.ok());
  EXPECT_EQ(w.size(), 4u);
  EXPECT_EQ(buf[4], 0);
}

TEST(ByteIo, ReaderFailsOnEveryShortRead) {
  const std::array<uint8_t, 3> bytes = {1, 2, 3};
  {
    ByteReader r(bytes);
    EXPECT_EQ(r.u32(), 0u);
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(r.u8(), 0);  // sticky
    EXPECT_EQ(r.position(), 0u);
  }
  {
    ByteReader r(bytes);
    EXPECT_EQ(r.u16(), 0x0201);
    EXPECT_TRUE(r.bytes(2).empty());
    EXPECT_FALSE(r.ok());
  }
  {
    ByteReader r(std::span<const uint8_t>{});
    EXPECT_EQ(r.u8(), 0);
    EXPECT_FALSE(r.ok());
  }
  {
    ByteReader r(bytes);
    EXPECT_TRUE(r.bytes(SIZE_MAX).empty());  // no overflow in the bounds check
    EXPECT_FALSE(r.ok());
  }
}

}  // namespace
}  // namespace dhr
