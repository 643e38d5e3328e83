// Why a datagram, a shard payload or a shard insertion was rejected. Decoders on the per-packet path
// return one of these instead of throwing; receivers drop the datagram and count the code.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>

namespace dhr {

enum class DecodeError : uint8_t {
  kNone = 0,
  kTruncated,          // fewer bytes than the layout requires
  kOversize,           // datagram longer than kMaxDatagramSize
  kTrailingBytes,      // bytes left over after the message
  kBadMagic,           // not a DHR datagram
  kWrongVersion,       // DHR datagram of another protocol version
  kUnknownType,        // message type this version does not define
  kBadReserved,        // a reserved field is not zero
  kBadToken,           // session token zero where one is required (or non-zero in Hello)
  kBadValue,           // a field outside its allowed range
  kNonFinite,          // NaN or infinity in a pose or field of view
  kBadPose,            // quaternion not (nearly) unit, position out of range
  kBadFov,             // field of view fails validate_fov
  kBadString,          // string too long or with control characters
  kBadPayload,         // visibility payload malformed (chunk layout, LZ4 data, sizes)
  kSessionMismatch,    // shard disagrees with the negotiated session (size, mask width)
  kInconsistentFrame,  // shard disagrees with earlier shards of its frame (count, view, overlap)
  kFutureFrame,        // shard for a frame the client has not requested yet
  kMissingReference,   // v2 shard coded against a frame the client does not hold (never decoded against another)
  kCount
};

inline constexpr size_t kDecodeErrorCount = static_cast<size_t>(DecodeError::kCount);

// Short stable name, e.g. "truncated" (for logs and statistics keys).
const char* to_string(DecodeError error);

// Per-code counters, for statistics ("count-friendly").
struct DecodeErrorCounts {
  std::array<uint64_t, kDecodeErrorCount> counts{};
  void add(DecodeError error) { ++counts[static_cast<size_t>(error) < kDecodeErrorCount ? static_cast<size_t>(error) : 0]; }
  uint64_t operator[](DecodeError error) const { return counts[static_cast<size_t>(error)]; }
  uint64_t total_errors() const;  // everything but kNone
};

}  // namespace dhr
