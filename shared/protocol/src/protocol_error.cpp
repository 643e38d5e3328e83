#include "protocol/protocol_error.hpp"

namespace dhr {

const char* to_string(DecodeError error) {
  switch (error) {
    case DecodeError::kNone: return "ok";
    case DecodeError::kTruncated: return "truncated";
    case DecodeError::kOversize: return "oversize";
    case DecodeError::kTrailingBytes: return "trailing bytes";
    case DecodeError::kBadMagic: return "bad magic";
    case DecodeError::kWrongVersion: return "wrong protocol version";
    case DecodeError::kUnknownType: return "unknown message type";
    case DecodeError::kBadReserved: return "reserved field not zero";
    case DecodeError::kBadToken: return "bad session token";
    case DecodeError::kBadValue: return "field out of range";
    case DecodeError::kNonFinite: return "non-finite value";
    case DecodeError::kBadPose: return "bad pose";
    case DecodeError::kBadFov: return "bad field of view";
    case DecodeError::kBadString: return "bad string";
    case DecodeError::kBadPayload: return "bad visibility payload";
    case DecodeError::kSessionMismatch: return "shard does not match the session";
    case DecodeError::kInconsistentFrame: return "shard inconsistent with its frame";
    case DecodeError::kFutureFrame: return "shard for a frame not yet requested";
    case DecodeError::kMissingReference: return "shard coded against a frame not held";
    case DecodeError::kCount: break;
  }
  return "unknown error";
}

uint64_t DecodeErrorCounts::total_errors() const {
  uint64_t sum = 0;
  for (size_t i = 1; i < counts.size(); ++i) sum += counts[i];
  return sum;
}

}  // namespace dhr
