// Visibility codec v2: payload header, checksum, decoding, and the encoder's shard packing (the block
// decisions are in codec_v2_decide.cpp, the bit-level coding in codec_v2_band.hpp).
#include "codec/codec_v2.hpp"

#include "codec_v2_band.hpp"
#include "codec_v2_decide.hpp"

#include <algorithm>
#include <array>
#include <cstring>

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

// Encodes rows [y0, y1) with block height bh. Stops after the first block row whose end would exceed
// `budget` bytes of coded stream; returns the first row not covered by the block rows that fit (y0: none).
// With a large enough budget the payload is complete in `out` (header included) and y1 is returned.
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
  const bool complete = coder.run(&decide, counts, [&](uint32_t next_row) {
    if (header_size(h.inter) + enc.size_if_finished() > budget) return false;
    fitted = next_row;
    return true;
  });
  if (!complete) return fitted;
  enc.finish();
  const uint32_t checksum = v2_checksum(rows_of(buffer, y0, y1));
  const size_t at = header_size(h.inter) - 4;
  for (int i = 0; i < 4; ++i) out[at + i] = static_cast<uint8_t>(checksum >> (8 * i));
  return y1;
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
  const size_t max_payload = std::clamp(options.max_payload, kMinShardPayload, kMaxShardPayload);
  const size_t budget = max_payload;  // header included
  const BlockDecider decide = make_block_decider(buffer, reference);
  Models models;
  V2Stats stats;
  std::vector<uint8_t> payload;
  BandCounts counts;
  for (uint32_t y = 0; y < buffer.height;) {
    uint32_t end = y;
    for (const uint32_t bh : {32u, 8u}) {
      BandCounts measure;
      end = encode_band(buffer, ref, distance, y, buffer.height, bh, budget, decide, models, payload, measure);
      ++stats.encode_passes;
      if (end == buffer.height && payload.size() <= budget) {
        counts = measure;
        break;  // the rest fitted: this encoding is the shard
      }
      if (end > y) {
        BandCounts final_counts;
        const uint32_t got = encode_band(buffer, ref, distance, y, end, bh, SIZE_MAX, decide, models, payload, final_counts);
        ++stats.encode_passes;
        if (got != end || payload.size() > budget) return false;  // cannot happen: the stream is a prefix
        counts = final_counts;
        break;
      }
    }
    if (end > y) {
      out_shards.push_back(EncodedShard{y * buffer.width, (end - y) * buffer.width, payload});
      stats.blocks += counts.blocks;
      stats.blocks_uniform += counts.uniform;
      stats.blocks_copied += counts.copied;
      stats.blocks_coded += counts.coded;
      stats.pixels_coded += counts.pixels_coded;
      y = end;
      continue;
    }
    // Not even 8 rows fit (noise): v1 chunks for those rows.
    const uint32_t rows = std::min(8u, buffer.height - y);
    VisibilityBuffer part = VisibilityBuffer::create(buffer.width, rows, buffer.light_count);
    const auto src = rows_of(buffer, y, y + rows);
    std::copy(src.begin(), src.end(), part.data.begin());
    std::vector<EncodedShard> v1;
    if (!encode_visibility(part, options, v1)) return false;
    for (EncodedShard& s : v1) {
      s.first_pixel += y * buffer.width;
      out_shards.push_back(std::move(s));
    }
    stats.v1_fallback_rows += rows;
    y += rows;
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
