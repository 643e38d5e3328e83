// Visibility codec v2: context-modelled binary arithmetic coding of per-light bit planes, intra or against a
// reference frame the client holds, in shards of whole rows that each decode on their own.
//
// A shard covers rows [y0, y1) of one eye's buffer (first_pixel = y0 * width, pixel_count = rows * width).
// Its payload:
//   u8  tag          kV2TagIntra, or kV2TagInter (coded against a reference frame)
//   u16 ref_distance (inter only) frame_number - reference frame number, 1..65535
//   u8  block_rows   height of the shard's blocks: 32 or 8
//   u32 checksum     of the decoded rows' mask bytes (v2_checksum): a shard decoded against another reference,
//                    or corrupted, is rejected instead of being shown
//   ... range-coded bits (codec/src/range_coder.hpp), models reset at the shard's start.
// The rows are cut into blocks of 32 x block_rows pixels, raster order. Per block and light a mode: uniform 0,
// uniform 1, copy from the reference at the block's vector, or coded; a coded block has a mode per 8x8
// sub-block. A mode's context holds what the decoder knows of that light around its region (all 0, all 1, both
// or nothing: inter, the reference under it at the block's predicted or coded vector; intra, the 8 rows above).
// Coded sub-blocks code each pixel with a context of, intra, 8 already known neighbours of the same light and the
// previous light's bit at that pixel; inter, 4 such neighbours and 5 reference bits around the displaced position.
// An inter block codes one vector (delta to the previous one) when any light reads the reference. Pixels
// outside the image, outside the shard's rows, or in blocks to the right in the current block row are 0 in
// every context, so encoder and decoder see the same neighbours. Rows that would not fit a shard even 8 at a
// time (noise) fall back to v1 chunks (codec.hpp), whose payloads start with a byte < kV2TagIntra.
#pragma once
#include "codec/codec.hpp"
#include "math/projection.hpp"
#include "protocol/protocol_error.hpp"
#include "visibility/visibility.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace dhr {

inline constexpr uint8_t kV2TagIntra = 0x20;
inline constexpr uint8_t kV2TagInter = 0x21;
inline constexpr size_t kV2IntraHeaderSize = 6;
inline constexpr size_t kV2InterHeaderSize = 8;
inline constexpr uint32_t kV2BlockWidth = 32;
inline constexpr int32_t kV2MaxVector = 255;  // per component, pixels
// Complete frames a client keeps per eye as references (the wire's contract: a server references an
// acknowledged frame only while fewer than this many newer frames of that eye were sent after it).
inline constexpr size_t kV2ReferenceFrames = 16;

// What a frame may be coded against: a frame the client has acknowledged holding in full.
struct V2Reference {
  const VisibilityBuffer* buffer = nullptr;  // same size and light count as the coded buffer
  uint64_t frame_number = 0;                 // older than the coded frame by 1..65535
  // Encoder hints, never sent: the cameras the coded and the reference buffer were traced with. Block vectors
  // are first guessed from them (rotation only); without them the search starts at the previous vectors.
  const Camera* current_camera = nullptr;
  const Camera* reference_camera = nullptr;
};

struct V2Stats {
  size_t shards = 0;
  size_t payload_bytes = 0;
  size_t datagram_bytes = 0;  // payload + kShardFixedSize per shard
  size_t blocks = 0;          // block x light
  size_t blocks_uniform = 0;
  size_t blocks_copied = 0;
  size_t blocks_coded = 0;
  size_t pixels_coded = 0;    // pixel x light coded bit by bit
  size_t v1_fallback_rows = 0;
  size_t encode_passes = 0;   // band encodings: one per shard, one more where 32-row blocks did not fit
};

// Encodes the whole buffer (intra when reference is null) into out_shards, in row order. False, with
// out_shards empty, for an inconsistent buffer or reference (sizes, light count, frame distance).
// Deterministic. The rows are cut into options.v2_ranges ranges coded on up to options.threads threads; the
// bytes depend on the ranges only.
bool encode_visibility_v2(const VisibilityBuffer& buffer, uint64_t frame_number, const V2Reference* reference,
                          const EncodeOptions& options, std::vector<EncodedShard>& out_shards,
                          V2Stats* out_stats = nullptr);

bool is_v2_payload(std::span<const uint8_t> payload);
// The frame a v2 payload needs as its reference; std::nullopt for intra or v1 payloads (and malformed ones,
// which decoding rejects).
std::optional<uint64_t> v2_reference_frame(std::span<const uint8_t> payload, uint64_t frame_number);

// Decodes one v2 payload into `frame` (the whole buffer's mask bytes). `reference`: the buffer of
// v2_reference_frame(), required for inter payloads (null -> kBadPayload). Never throws and never writes
// outside the shard's rows; returns kBadPayload for a malformed payload or a checksum mismatch (the rows may
// then hold garbage and must not be used).
DecodeError decode_shard_payload_v2(std::span<const uint8_t> payload, uint32_t first_pixel, uint32_t pixel_count,
                                    uint32_t width, uint32_t height, uint32_t light_count,
                                    const VisibilityBuffer* reference, std::span<uint8_t> frame);

// The checksum v2 shards carry: of `bytes`, 32 bits, deterministic.
uint32_t v2_checksum(std::span<const uint8_t> bytes);

}  // namespace dhr
