// Visibility codec v2: payload header, checksum, decoding, and the encoder's shard packing (the block
// decisions are in codec_v2_decide.cpp, the bit-level coding in codec_v2_band.hpp).
#include "codec/codec_v2.hpp"

#include "codec_v2_band.hpp"
#include "codec_v2_decide.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#include <exception>
#include <system_error>
#include <thread>

namespace dhr {

using namespace codec_detail;

namespace {

struct Header {
  bool inter = false;
  uint16_t ref_distance = 0;
  uint8_t block_rows = 32;
  uint32_t checksum = 0;
};

size_t header_size(bool inter) { return inter ? kV2InterHeaderSize : kV2IntraHeaderSize; }

void write_header(const Header& h, std::vector<uint8_t>& out) {
  out.push_back(h.inter ? kV2TagInter : kV2TagIntra);
  if (h.inter) {
    out.push_back(static_cast<uint8_t>(h.ref_distance));
    out.push_back(static_cast<uint8_t>(h.ref_distance >> 8));
  }
  out.push_back(h.block_rows);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(h.checksum >> (8 * i)));
}

bool read_header(std::span<const uint8_t> p, Header& h) {
  if (p.empty() || (p[0] != kV2TagIntra && p[0] != kV2TagInter)) return false;
  h.inter = p[0] == kV2TagInter;
  if (p.size() < header_size(h.inter)) return false;
  size_t i = 1;
  if (h.inter) {
    h.ref_distance = static_cast<uint16_t>(p[1] | p[2] << 8);
    if (h.ref_distance == 0) return false;
    i = 3;
  }
  h.block_rows = p[i];
  if (h.block_rows != 8 && h.block_rows != 32) return false;
  h.checksum = 0;
  for (int b = 0; b < 4; ++b) h.checksum |= static_cast<uint32_t>(p[i + 1 + b]) << (8 * b);
  return true;
}

bool same_shape(const VisibilityBuffer& a, const VisibilityBuffer& b) {
  return a.width == b.width && a.height == b.height && a.light_count == b.light_count &&
         a.mask_bits == b.mask_bits && a.data.size() == b.data.size();
}

std::span<const uint8_t> rows_of(const VisibilityBuffer& b, uint32_t y0, uint32_t y1) {
  const size_t row = size_t{b.width} * b.bytes_per_mask();
  return std::span<const uint8_t>(b.data).subspan(y0 * row, (y1 - y0) * row);
}

// Encodes rows [y0, y1) with block height bh, as many whole block rows as fit `budget` bytes (header
// included): `out` holds the finished payload of rows [y0, returned row); y0 when not even one block row fits.
// One pass: the coder's state is kept at each block row's end, and the row that overflowed is undone.
uint32_t encode_band(const VisibilityBuffer& buffer, const VisibilityBuffer* ref, uint16_t ref_distance,
                     uint32_t y0, uint32_t y1, uint32_t bh, size_t budget, const BlockDecider& decide,
                     Models& models, std::vector<uint8_t>& out, BandCounts& counts) {
  out.clear();
  Header h{ref != nullptr, ref_distance, static_cast<uint8_t>(bh), 0};  // checksum patched in when complete
  write_header(h, out);
  const BandGeometry g{buffer.width, buffer.height, y0, y1, bh, buffer.light_count, buffer.bytes_per_mask()};
  models.reset();
  BitEncoder enc(out);
  uint8_t* cur = const_cast<uint8_t*>(buffer.data.data());  // read only: the encoder never writes pixels
  BandCoder<BitEncoder> coder(enc, g, cur, ref != nullptr ? ref->data.data() : nullptr, models);
  uint32_t fitted = y0;
  BitEncoder::State kept = enc.state();
  BandCounts kept_counts = counts;
  coder.run(&decide, counts, [&](uint32_t next_row) {
    if (header_size(h.inter) + enc.size_if_finished() > budget) return false;
    fitted = next_row;
    kept = enc.state();
    kept_counts = counts;
    return true;
  });
  if (fitted == y0) return y0;
  enc.restore(kept);  // a no-op when every row fitted
  counts = kept_counts;
  enc.finish();
  const uint32_t checksum = v2_checksum(rows_of(buffer, y0, fitted));
  const size_t at = header_size(h.inter) - 4;
  for (int i = 0; i < 4; ++i) out[at + i] = static_cast<uint8_t>(checksum >> (8 * i));
  return fitted;
}

}  // namespace

uint32_t v2_checksum(std::span<const uint8_t> bytes) {
  // Four independent multiply-xorshift lanes over 8-byte words (a 2.2 MB buffer in ~0.1 ms), then the tail.
  std::array<uint64_t, 4> h = {0x9E3779B97F4A7C15ull ^ bytes.size(), 0xC2B2AE3D27D4EB4Full, 0x165667B19E3779F9ull,
                               0x27D4EB2F165667C5ull};
  size_t i = 0;
  for (; i + 32 <= bytes.size(); i += 32) {
    for (size_t k = 0; k < 4; ++k) {
      uint64_t w;
      std::memcpy(&w, bytes.data() + i + 8 * k, 8);  // host order: both sides are little-endian
      h[k] = (h[k] ^ w) * 0xFF51AFD7ED558CCDull;
      h[k] ^= h[k] >> 32;
    }
  }
  uint64_t r = h[0];
  for (size_t k = 1; k < 4; ++k) {
    r = (r ^ h[k]) * 0xC4CEB9FE1A85EC53ull;
    r ^= r >> 32;
  }
  for (; i < bytes.size(); ++i) r = (r ^ bytes[i]) * 0x100000001B3ull;
  r ^= r >> 29;
  return static_cast<uint32_t>(r ^ (r >> 32));
}

bool is_v2_payload(std::span<const uint8_t> payload) {
  return !payload.empty() && (payload[0] == kV2TagIntra || payload[0] == kV2TagInter);
}

std::optional<uint64_t> v2_reference_frame(std::span<const uint8_t> payload, uint64_t frame_number) {
  Header h;
  if (!read_header(payload, h) || !h.inter || h.ref_distance > frame_number) return std::nullopt;
  return frame_number - h.ref_distance;
}

DecodeError decode_shard_payload_v2(std::span<const uint8_t> payload, uint32_t first_pixel, uint32_t pixel_count,
                                    uint32_t width, uint32_t height, uint32_t light_count,
                                    const VisibilityBuffer* reference, std::span<uint8_t> frame) {
  if (width == 0 || height == 0 || width > kMaxBufferDimension || height > kMaxBufferDimension ||
      light_count > kMaxLights || pixel_count == 0 || first_pixel % width != 0 || pixel_count % width != 0) {
    return DecodeError::kBadPayload;
  }
  const uint32_t mb = mask_bytes(mask_width_for_light_count(light_count));
  const uint32_t y0 = first_pixel / width, y1 = y0 + pixel_count / width;
  if (y1 > height || frame.size() != size_t{width} * height * mb) return DecodeError::kBadPayload;
  Header h;
  if (!read_header(payload, h)) return DecodeError::kBadPayload;
  if (h.inter && (reference == nullptr || reference->width != width || reference->height != height ||
                  reference->light_count != light_count || reference->data.size() != frame.size())) {
    return DecodeError::kBadPayload;
  }
  const BandGeometry g{width, height, y0, y1, h.block_rows, light_count, mb};
  Models models;
  BitDecoder dec(payload.subspan(header_size(h.inter)));
  BandCoder<BitDecoder> coder(dec, g, frame.data(), h.inter ? reference->data.data() : nullptr, models);
  BandCounts counts;
  if (!coder.run(nullptr, counts) || dec.overrun() > 4) return DecodeError::kBadPayload;
  const size_t row = size_t{width} * mb;
  if (v2_checksum(frame.subspan(y0 * row, (y1 - y0) * row)) != h.checksum) return DecodeError::kBadPayload;
  return DecodeError::kNone;
}

namespace {

// One range's shards (rows [y0, y1)), in row order, with their counts; what the whole-buffer encoder then
// concatenates. ok is false when the range could not be coded: a v1 fallback that failed, an exception (out of
// memory), or a finished shard over its budget (which size_if_finished rules out).
struct RangeResult {
  std::vector<EncodedShard> shards;
  V2Stats stats;
  bool ok = true;
};

RangeResult encode_range(const VisibilityBuffer& buffer, const V2Reference* reference, uint16_t distance, uint32_t y0,
                         uint32_t y1, const EncodeOptions& options) {
  RangeResult r;
  const VisibilityBuffer* ref = reference != nullptr ? reference->buffer : nullptr;
  const size_t budget = std::clamp(options.max_payload, kMinShardPayload, kMaxShardPayload);  // header included
  const BlockDecider decide = make_block_decider(buffer, reference);
  Models models;
  std::vector<uint8_t> payload;
  BandCounts counts;
  for (uint32_t y = y0; y < y1;) {
    uint32_t end = y;
    for (const uint32_t bh : {32u, 8u}) {  // 8-row blocks only where not even one row of 32-row blocks fits
      counts = BandCounts{};
      end = encode_band(buffer, ref, distance, y, y1, bh, budget, decide, models, payload, counts);
      ++r.stats.encode_passes;
      if (end > y) {
        if (payload.size() > budget) {  // cannot happen: size_if_finished bounds the finished size
          r.ok = false;
          return r;
        }
        break;
      }
    }
    if (end > y) {
      r.shards.push_back(EncodedShard{y * buffer.width, (end - y) * buffer.width, payload});
      r.stats.blocks += counts.blocks;
      r.stats.blocks_uniform += counts.uniform;
      r.stats.blocks_copied += counts.copied;
      r.stats.blocks_coded += counts.coded;
      r.stats.pixels_coded += counts.pixels_coded;
      y = end;
      continue;
    }
    // Not even 8 rows fit (noise): v1 chunks for those rows.
    const uint32_t rows = std::min(8u, y1 - y);
    VisibilityBuffer part = VisibilityBuffer::create(buffer.width, rows, buffer.light_count);
    const auto src = rows_of(buffer, y, y + rows);
    std::copy(src.begin(), src.end(), part.data.begin());
    std::vector<EncodedShard> v1;
    if (!encode_visibility(part, options, v1)) {
      r.ok = false;
      return r;
    }
    for (EncodedShard& s : v1) {
      s.first_pixel += y * buffer.width;
      r.shards.push_back(std::move(s));
    }
    r.stats.v1_fallback_rows += rows;
    y += rows;
  }
  return r;
}

// Where the ranges start: row 0, then at 32-row boundaries that split the buffer's expected coding work evenly.
// The work is estimated from a sample (every 2nd row, every 4th pixel): each sampled pixel costs 1 (every block is
// decided, uniform or not) and each bit in which its mask differs from the sampled one left of it or above it
// kChangeWeight (coded pixels lie at such changes, and every differing light's plane is coded there). Each range
// holds at least 32 rows. The weight was chosen by timing each of two ranges on one thread: 40 split the living
// room, its dense version, 64 lights and the area room's levels within 10 % of even (docs/performance.md,
// "Encoding in one pass, on two threads").
constexpr uint64_t kChangeWeight = 40;

// The bits set in x, in a few instructions: std::popcount is a library call without the POPCNT instruction, which
// the baseline x86-64 this builds for lacks (it made the estimate cost more than the balance saved).
uint32_t bits_set(uint32_t x) {
  x -= (x >> 1) & 0x55555555u;
  x = (x & 0x33333333u) + ((x >> 2) & 0x33333333u);
  return (((x + (x >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24;
}

std::vector<uint32_t> range_starts(const VisibilityBuffer& buffer, size_t ranges) {
  std::vector<uint32_t> starts{0};
  ranges = std::clamp<size_t>(ranges, 1, 64);
  if (ranges == 1 || buffer.height < 64) return starts;
  const uint32_t bands = (buffer.height + 31) / 32;
  const size_t mb = buffer.bytes_per_mask(), row = size_t{buffer.width} * mb;
  std::vector<uint64_t> work(bands, 0);
  with_mask_type(static_cast<uint32_t>(mb), [&]<typename Mask>() {
    for (uint32_t y = 2; y < buffer.height; y += 2) {
      const uint8_t* cur = buffer.data.data() + size_t{y} * row;
      const uint8_t* up = cur - 2 * row;
      uint64_t changes = 0;
      for (size_t x = 4; x < buffer.width; x += 4) {
        const Mask m = at<Mask>(cur, x);
        const uint32_t left = static_cast<uint32_t>(m ^ at<Mask>(cur, x - 4));
        const uint32_t above = static_cast<uint32_t>(m ^ at<Mask>(up, x));
        if ((left | above) != 0) changes += bits_set(left) + bits_set(above);
      }
      work[y / 32] += changes * kChangeWeight + buffer.width / 4;
    }
  });
  uint64_t total = 0;
  for (const uint64_t w : work) total += w;
  uint64_t sum = 0;
  size_t next = 1;
  for (uint32_t b = 1; b < bands && next < ranges; ++b) {
    sum += work[b - 1];
    const bool due = total > 0 ? sum * ranges >= total * next : uint64_t{b} * ranges >= uint64_t{bands} * next;
    if (due && b * 32 + 32 <= buffer.height) {
      starts.push_back(b * 32);
      ++next;
    }
  }
  return starts;
}

}  // namespace

bool encode_visibility_v2(const VisibilityBuffer& buffer, uint64_t frame_number, const V2Reference* reference,
                          const EncodeOptions& options, std::vector<EncodedShard>& out_shards, V2Stats* out_stats) {
  out_shards.clear();
  if (buffer.width == 0 || buffer.height == 0 || buffer.width > kMaxBufferDimension ||
      buffer.height > kMaxBufferDimension || buffer.light_count > kMaxLights ||
      buffer.mask_bits != mask_width_for_light_count(buffer.light_count) ||
      buffer.data.size() != buffer.size_bytes()) {
    return false;
  }
  const VisibilityBuffer* ref = reference != nullptr ? reference->buffer : nullptr;
  uint16_t distance = 0;
  if (ref != nullptr) {
    if (!same_shape(buffer, *ref) || reference->frame_number >= frame_number ||
        frame_number - reference->frame_number > 65535) {
      return false;
    }
    distance = static_cast<uint16_t>(frame_number - reference->frame_number);
  }
  const std::vector<uint32_t> starts = range_starts(buffer, options.v2_ranges);
  std::vector<RangeResult> results(starts.size());
  const auto run = [&](size_t i) {
    const uint32_t y1 = i + 1 < starts.size() ? starts[i + 1] : buffer.height;
    try {
      results[i] = encode_range(buffer, reference, distance, starts[i], y1, options);
    } catch (const std::exception&) {  // out of memory: the frame is not sent, never a crash
      results[i].ok = false;
    }
  };
  // Each worker takes the next range not yet taken; the calling thread is one of them.
  const size_t workers = std::clamp<size_t>(options.threads, 1, starts.size());
  std::atomic<size_t> next{0};
  const auto work = [&] {
    for (size_t i = next++; i < starts.size(); i = next++) run(i);
  };
  std::vector<std::thread> helpers;
  for (size_t w = 1; w < workers; ++w) {
    try {
      helpers.emplace_back(work);
    } catch (const std::system_error&) {  // no thread to be had: the calling thread codes the rest
      break;
    }
  }
  work();
  for (std::thread& t : helpers) t.join();

  V2Stats stats;
  for (RangeResult& r : results) {
    if (!r.ok) {
      out_shards.clear();
      return false;
    }
    for (EncodedShard& s : r.shards) out_shards.push_back(std::move(s));
    stats.blocks += r.stats.blocks;
    stats.blocks_uniform += r.stats.blocks_uniform;
    stats.blocks_copied += r.stats.blocks_copied;
    stats.blocks_coded += r.stats.blocks_coded;
    stats.pixels_coded += r.stats.pixels_coded;
    stats.v1_fallback_rows += r.stats.v1_fallback_rows;
    stats.encode_passes += r.stats.encode_passes;
  }
  if (out_shards.size() > 65535) {
    out_shards.clear();
    return false;
  }
  stats.shards = out_shards.size();
  for (const EncodedShard& s : out_shards) stats.payload_bytes += s.payload.size();
  stats.datagram_bytes = stats.payload_bytes + stats.shards * kShardFixedSize;
  if (out_stats) *out_stats = stats;
  return true;
}

}  // namespace dhr
