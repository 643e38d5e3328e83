// How the structured fuzz targets read their parameters from the front of an input, in one place so
// that the seed generator writes exactly what the targets read. Raw fields are mapped into small ranges
// here (a frame of at most a few hundred KiB), so no input can make a target allocate absurdly.
#pragma once
#include "protocol/protocol.hpp"
#include "fuzz_support.hpp"

#include <cstdint>

namespace dhr::fuzz {

// fuzz_shard_payload: u8 mode, u16 width-1, u16 height-1, u32 first_pixel, u32 pixel_count-1, payload.
struct ShardPayloadParams {
  static constexpr uint32_t kMaxWidth = 256;
  static constexpr uint32_t kMaxHeight = 64;
  // mode bits 0-1: mask width 8/16/32, or 3 = an invalid width (24 bits); bit 2: region taken raw
  // (unbounded, exercises the range checks); bit 3: frame one byte longer than width*height masks.
  uint8_t mode = 0;
  uint32_t width = 1;
  uint32_t height = 1;
  uint32_t first_pixel = 0;
  uint32_t pixel_count = 1;

  static ShardPayloadParams read(Reader& r) {
    ShardPayloadParams p;
    p.mode = r.u8();
    p.width = 1 + r.u16() % kMaxWidth;
    p.height = 1 + r.u16() % kMaxHeight;
    const uint32_t first = r.u32();
    const uint32_t count = r.u32();
    const uint32_t total = p.width * p.height;
    if (p.mode & 4) {
      p.first_pixel = first;
      p.pixel_count = count;
    } else {
      p.first_pixel = first % total;
      p.pixel_count = 1 + count % (total - p.first_pixel);
    }
    return p;
  }
  // Inverse of read() for in-range values (mode bit 2 clear).
  void write(Bytes& out) const {
    put_u8(out, mode);
    put_u16(out, static_cast<uint16_t>(width - 1));
    put_u16(out, static_cast<uint16_t>(height - 1));
    put_u32(out, first_pixel);
    put_u32(out, pixel_count - 1);
  }
};

// fuzz_shard_payload_v2: u8 mode, u8 width-1, u8 height-1, u8 first_row, u8 rows-1, payload. Mode bits 0-1:
// lights 3, 9, 17 or 32; bit 2: decode against the reference below (else none); bit 3: rows taken raw
// (unbounded, exercises the range checks).
struct ShardPayloadV2Params {
  static constexpr uint32_t kMaxWidth = 128;
  static constexpr uint32_t kMaxHeight = 64;
  uint8_t mode = 0;
  uint32_t width = 1;
  uint32_t height = 1;
  uint32_t first_row = 0;
  uint32_t rows = 1;

  uint32_t light_count() const {
    const uint32_t counts[4] = {3, 9, 17, 32};
    return counts[mode & 3u];
  }
  static ShardPayloadV2Params read(Reader& r) {
    ShardPayloadV2Params p;
    p.mode = r.u8();
    p.width = 1 + r.u8() % kMaxWidth;
    p.height = 1 + r.u8() % kMaxHeight;
    const uint32_t first = r.u8(), rows = r.u8();
    if (p.mode & 8) {
      p.first_row = first;
      p.rows = rows + 1;
    } else {
      p.first_row = first % p.height;
      p.rows = 1 + rows % (p.height - p.first_row);
    }
    return p;
  }
  void write(Bytes& out) const {
    put_u8(out, mode);
    put_u8(out, static_cast<uint8_t>(width - 1));
    put_u8(out, static_cast<uint8_t>(height - 1));
    put_u8(out, static_cast<uint8_t>(first_row));
    put_u8(out, static_cast<uint8_t>(rows - 1));
  }
};

// The reference frame of fuzz_shard_payload_v2 (and of its seeds): a deterministic pattern of soft-edged
// blobs, different per light.
inline VisibilityBuffer v2_fuzz_reference(uint32_t width, uint32_t height, uint32_t light_count) {
  VisibilityBuffer b = VisibilityBuffer::create(width, height, light_count);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      uint32_t m = 0;
      for (uint32_t l = 0; l < light_count; ++l)
        m |= ((x + 3 * l) / (5 + l % 4) + (y + l) / (4 + l % 3)) % 3 == 0 ? 1u << l : 0u;
      b.set(x, y, m);
    }
  return b;
}

// fuzz_codec_roundtrip: u8 lights, u16 width-1, u16 height-1, u16 max_payload, u16 uniform_min_bytes,
// u8 flags, then fill bytes.
struct CodecRoundTripParams {
  static constexpr uint32_t kMaxWidth = 320;
  static constexpr uint32_t kMaxHeight = 96;
  enum Fill : uint8_t {
    kRuns = 0,    // (u16 run length - 1, mask) pairs, cycled: long uniform stretches and short ones
    kCyclic = 1,  // the fill bytes repeated verbatim: mostly incompressible
    kSparse = 2,  // zero masks except a mask from the fill bytes every (byte + 1) pixels
  };
  uint32_t light_count = 0;
  uint32_t width = 1;
  uint32_t height = 1;
  uint16_t max_payload = 0;        // raw: the encoder clamps it (tested on purpose)
  uint16_t uniform_min_bytes = 0;  // raw as well
  bool row_aligned = false;
  Fill fill = kRuns;

  static CodecRoundTripParams read(Reader& r) {
    CodecRoundTripParams p;
    p.light_count = r.u8() % 33;
    p.width = 1 + r.u16() % kMaxWidth;
    p.height = 1 + r.u16() % kMaxHeight;
    p.max_payload = r.u16();
    p.uniform_min_bytes = r.u16();
    const uint8_t flags = r.u8();
    p.row_aligned = (flags & 1) != 0;
    p.fill = static_cast<Fill>((flags >> 1) % 3);
    return p;
  }
  void write(Bytes& out) const {
    put_u8(out, static_cast<uint8_t>(light_count));
    put_u16(out, static_cast<uint16_t>(width - 1));
    put_u16(out, static_cast<uint16_t>(height - 1));
    put_u16(out, max_payload);
    put_u16(out, uniform_min_bytes);
    put_u8(out, static_cast<uint8_t>((row_aligned ? 1 : 0) | (fill << 1)));
  }
};

// fuzz_reassembler: the session, then operations until the input ends.
struct ReassemblerParams {
  static constexpr uint32_t kMaxWidth = 128;
  static constexpr uint32_t kMaxHeight = 48;
  uint32_t width = 1;
  uint32_t height = 1;
  uint32_t light_count = 0;
  uint32_t frames_in_flight = 2;  // 2..6
  uint32_t max_payload = 64;      // 64..kMaxShardPayload: both the encoder budget and the config
  bool limit_frames = false;      // call set_newest_requested_frame(newest_requested)
  uint8_t newest_requested = 0;

  static ReassemblerParams read(Reader& r) {
    ReassemblerParams p;
    p.width = 1 + r.u16() % kMaxWidth;
    p.height = 1 + r.u16() % kMaxHeight;
    p.light_count = r.u8() % 33;
    p.frames_in_flight = 2 + r.u8() % 5;
    p.max_payload = 64 + r.u16() % static_cast<uint32_t>(kMaxShardPayload - 64 + 1);
    const uint8_t flags = r.u8();
    p.limit_frames = (flags & 1) != 0;
    p.newest_requested = r.u8();
    return p;
  }
  void write(Bytes& out) const {
    put_u16(out, static_cast<uint16_t>(width - 1));
    put_u16(out, static_cast<uint16_t>(height - 1));
    put_u8(out, static_cast<uint8_t>(light_count));
    put_u8(out, static_cast<uint8_t>(frames_in_flight - 2));
    put_u16(out, static_cast<uint16_t>(max_payload - 64));
    put_u8(out, limit_frames ? 1 : 0);
    put_u8(out, newest_requested);
  }
};

// Operation codes of fuzz_reassembler (the low 2 bits of the op byte).
enum class ReassemblerOp : uint8_t {
  kGenuine = 0,    // u8 frame, u8 eye, u16 shard index: a real shard of that frame's synthetic buffer
  kGenuine2 = 1,   // the same (so half of random ops are real shards)
  kForged = 2,     // a shard with fields and payload from the input (see fuzz_reassembler.cpp)
  kControl = 3,    // op >> 2: 0 reset, 1 re-insert the previous shard, 2 set newest requested frame (u8)
};

}  // namespace dhr::fuzz
