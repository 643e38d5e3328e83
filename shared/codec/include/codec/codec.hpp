// Visibility codec: a VisibilityBuffer -> shards of at most kMaxShardPayload bytes, each decodable on
// its own, so a lost datagram costs only its region of the image.
//
// A shard covers a contiguous run of pixels in row-major order, [first_pixel, first_pixel + pixel_count)
// (whole rows when EncodeOptions::row_aligned asks for it, where a row fits in a shard). Its payload is
// a sequence of chunks that exactly tile that run, each independently decodable:
//   kUniform: u8 kind=0, u32 pixel_count, mask (1/2/4 bytes LE)        -- a run of identical masks
//   kLz4:     u8 kind=1, u32 pixel_count, u16 size, LZ4 block of size  -- decompresses to count*mask bytes
//   kRaw:     u8 kind=2, u32 pixel_count, count*mask bytes             -- incompressible data
// Long runs of identical masks (empty sky, fully lit floor) become uniform chunks and cost ~0 bytes.
#pragma once
#include "protocol/protocol.hpp"
#include "protocol/protocol_error.hpp"
#include "visibility/visibility.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace dhr {

enum class ChunkKind : uint8_t { kUniform = 0, kLz4 = 1, kRaw = 2 };

inline constexpr size_t kMinShardPayload = 64;

struct EncodeOptions {
  size_t max_payload = kMaxShardPayload;  // per-shard payload budget, clamped to [kMinShardPayload, kMaxShardPayload]
  // Runs of identical masks this long (bytes, >= 32) become uniform chunks. Shorter runs compress well
  // inside LZ4 anyway, and splitting LZ4 streams at every half-row run costs more than it saves
  // (measured: 1024 -> +50 % bytes on a shadowed room, 4096..65536 -> the same as 8192).
  size_t uniform_min_bytes = 8192;
  // End shards on row boundaries where a shard holds >= 1 row, so a lost shard never costs part of a
  // row that other shards carry. Off by default: on real traced buffers it costs 1-7 % more bytes
  // (each shard wastes half a row's worth of budget on average) for little gain.
  bool row_aligned = false;
  // v2 only: the rows are cut into this many ranges that are coded on their own, each into its own shards, so
  // they can be coded at once. Cuts lie at multiples of 32 rows where they split the estimated coding work evenly
  // (each range at least 32 rows; fewer ranges for small buffers). The bytes depend on this, never on `threads`.
  size_t v2_ranges = 2;
  // v2 only: at most this many threads code the ranges (the calling thread is one of them; 1: it alone).
  size_t threads = 2;
};

struct CodecStats {
  size_t raw_bytes = 0;       // uncompressed buffer size
  size_t payload_bytes = 0;   // sum of shard payloads
  size_t datagram_bytes = 0;  // payload + kShardFixedSize per shard: what goes on the wire
  size_t shard_count = 0;
  size_t uniform_chunks = 0;
  size_t uniform_pixels = 0;
  size_t lz4_chunks = 0;
  size_t lz4_pixels = 0;
  size_t raw_chunks = 0;
  size_t raw_pixels = 0;
  size_t row_trims = 0;  // shards shortened to end on a row boundary
};

struct EncodedShard {
  uint32_t first_pixel = 0;
  uint32_t pixel_count = 0;
  std::vector<uint8_t> payload;  // 1..max_payload bytes
};

// Upper bounds for any buffer of this size and mask width (for preallocation and for rejecting absurd
// shard counts on the receiving side).
struct CodecBound {
  size_t max_shards = 0;
  size_t max_payload_bytes = 0;  // sum over all shards
};
CodecBound codec_bound(uint32_t width, uint32_t height, MaskWidth mask_bits, size_t max_payload = kMaxShardPayload);

// Encodes the whole buffer into out_shards (in pixel order). Returns false, with out_shards empty, when
// the buffer is inconsistent (data size, dimensions 0 or above kMaxBufferDimension) or would need more
// than 65535 shards. Deterministic.
bool encode_visibility(const VisibilityBuffer& buffer, const EncodeOptions& options,
                       std::vector<EncodedShard>& out_shards, CodecStats* out_stats = nullptr);

// Decodes one shard payload into `frame`, the bytes of the whole buffer (width * height masks of
// mask_bits). Checks every chunk against the region and the payload size, and LZ4 blocks with
// LZ4_decompress_safe against their exact expected size. Never throws and never writes outside
// [first_pixel, first_pixel + pixel_count); on error that region may be partly written.
DecodeError decode_shard_payload(std::span<const uint8_t> payload, uint32_t first_pixel, uint32_t pixel_count,
                                 MaskWidth mask_bits, std::span<uint8_t> frame);

// Size of the buffer compressed as one LZ4 block (LZ4_compress_default): the reference the shardable
// scheme is measured against. 0 on failure.
size_t whole_frame_lz4_size(std::span<const uint8_t> bytes);

// Encoded shards (of either codec) as protocol messages for one (frame, eye), every shard carrying `view`.
std::vector<VisibilityShard> shards_as_messages(const VisibilityBuffer& buffer, uint64_t frame_number, Eye eye,
                                                const View& view, const std::vector<EncodedShard>& encoded);

// The encoded buffer as protocol messages for one (frame, eye), every shard carrying `view`.
// Empty when encode_visibility fails.
std::vector<VisibilityShard> make_visibility_shards(const VisibilityBuffer& buffer, uint64_t frame_number, Eye eye,
                                                    const View& view, const EncodeOptions& options = {},
                                                    CodecStats* out_stats = nullptr);

}  // namespace dhr
