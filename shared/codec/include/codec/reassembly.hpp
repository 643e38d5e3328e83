// Client-side reassembly of visibility shards into per-eye frames.
//
// Policy (per eye): the newest frame wins. A shard of a frame at or older than the newest complete frame
// is dropped as late; at most max_frames_in_flight frames are held (the newest complete one plus newer
// incomplete ones); when a newer frame needs a slot, the oldest incomplete frame is evicted, and a shard
// older than every held incomplete frame is dropped. When a frame completes, older frames are released.
// Incomplete frames are usable region by region: row_valid says which rows fully arrived (and
// received_ranges exactly which pixels), so the client falls back to prediction for the rest. Memory is allocated at most once per slot, never per shard, and is
// bounded by (2 * max_frames_in_flight + 1 + 2 * reference_frames) buffers whatever arrives. Complete frames are
// kept (reference_frames per eye) as references for codec v2 inter shards, which decode only against the
// exact frame they name (else kMissingReference). Deterministic; not thread-safe.
#pragma once
#include "codec/codec.hpp"
#include "codec/codec_v2.hpp"
#include "codec/visibility_frame.hpp"
#include "math/pose.hpp"
#include "protocol/protocol.hpp"
#include "protocol/protocol_error.hpp"
#include "visibility/visibility.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace dhr {

struct ReassemblerConfig {
  uint32_t width = 0;  // negotiated per-eye buffer size (Welcome::buffer_width/height)
  uint32_t height = 0;
  uint32_t light_count = 0;          // bits per mask (Welcome::used_mask_bits()); the mask width follows
  size_t max_frames_in_flight = 4;   // per eye, >= 2
  size_t max_payload = kMaxShardPayload;  // the server's shard budget, for the shard-count bound
  // Complete frames kept per eye as references for codec v2 shards (0: v1 only; a v2 inter shard is then
  // rejected with kMissingReference).
  size_t reference_frames = 0;
};

// A frame in the reassembler: the visibility frame itself (what the client publishes, VisibilityFrame) and
// exactly what of it arrived.
struct ReassembledFrame {
  VisibilityFrame visibility;  // rows that did not arrive are zero; row_valid has one entry per row
  // Exactly what arrived: disjoint pixel ranges [first, end), row-major, sorted (finer than row_valid
  // where a shard boundary falls inside a row).
  std::vector<std::pair<uint32_t, uint32_t>> received_ranges;
  size_t pixels_received = 0;
  uint16_t shard_count = 0;
  uint16_t shards_received = 0;
  bool complete() const { return pixels_received == visibility.buffer.pixel_count(); }
};

enum class InsertStatus : uint8_t {
  kAccepted,   // stored; its frame is still incomplete
  kCompleted,  // stored, and it completed its frame
  kDuplicate,  // this shard (or its complete frame) was already there
  kLate,       // its frame is older than the newest complete frame or than every held frame
  kRejected,   // invalid: see InsertResult::error
};
const char* to_string(InsertStatus status);

struct InsertResult {
  InsertStatus status = InsertStatus::kRejected;
  DecodeError error = DecodeError::kNone;  // set when status == kRejected
};

struct ReassemblerStats {
  uint64_t shards_accepted = 0;  // kAccepted + kCompleted
  uint64_t shards_duplicate = 0;
  uint64_t shards_late = 0;
  uint64_t shards_rejected = 0;
  uint64_t frames_started = 0;
  uint64_t frames_completed = 0;
  uint64_t frames_evicted = 0;     // incomplete frames pushed out by newer ones
  uint64_t frames_superseded = 0;  // incomplete frames released because a newer frame completed
  DecodeErrorCounts rejections;
};

class VisibilityReassembler {
 public:
  // Throws std::invalid_argument for an unusable configuration (setup code).
  explicit VisibilityReassembler(const ReassemblerConfig& config);

  // Never throws (besides std::bad_alloc when a slot is first used). Validates the shard against the
  // session (size, mask width, shard-count bound) and against earlier shards of its frame (shard count,
  // view, scene time, overlapping regions); the payload is decoded into scratch first, so a rejected shard
  // changes nothing.
  InsertResult insert(const VisibilityShard& shard);

  // Shards of frames newer than `frame` are rejected with kFutureFrame (the client knows which frames it
  // sent poses for). Unset by default.
  void set_newest_requested_frame(uint64_t frame) { newest_requested_ = frame; }

  // Newest frame holding any data (may be incomplete), or null. Valid until the next insert()/reset().
  const ReassembledFrame* latest(Eye eye) const;
  // Newest complete frame, or null. Valid until the next insert()/reset().
  const ReassembledFrame* latest_complete(Eye eye) const;
  // The newest complete frame kept as a v2 reference (what the client acknowledges), if any.
  std::optional<uint64_t> newest_reference(Eye eye) const;

  const ReassemblerStats& stats() const { return stats_; }
  const ReassemblerConfig& config() const { return config_; }
  size_t max_shards_per_frame() const { return max_shards_; }
  size_t memory_bytes() const;  // bytes currently allocated for frames and scratch
  void reset();                 // forget all frames (keeps allocations)

 private:
  struct Slot {
    bool in_use = false;
    bool allocated = false;
    ReassembledFrame frame;
    std::vector<uint8_t> shard_received;  // per shard index
    std::vector<uint32_t> row_pixels;     // received pixels per row
  };
  struct Reference {
    uint64_t frame = 0;
    VisibilityBuffer buffer;
  };
  struct EyeState {
    std::vector<Slot> slots;
    std::optional<uint64_t> complete_frame;  // newest complete frame number
    std::vector<Reference> references;       // ring of the newest complete frames (reference_frames)
    size_t references_used = 0;
    size_t next_reference = 0;
  };
  const VisibilityBuffer* find_reference(const EyeState& eye, uint64_t frame) const;
  void keep_reference(EyeState& eye, const ReassembledFrame& frame);

  Slot* find_slot(EyeState& eye, uint64_t frame);
  Slot* claim_slot(EyeState& eye, uint64_t frame, bool& out_late);
  void start_frame(Slot& slot, const VisibilityShard& shard);
  void commit(Slot& slot, const VisibilityShard& shard);
  void release_older(EyeState& eye, uint64_t frame);
  InsertResult reject(DecodeError error);

  ReassemblerConfig config_;
  MaskWidth mask_bits_;
  size_t max_shards_ = 0;
  std::array<EyeState, 2> eyes_;
  std::vector<uint8_t> scratch_;  // a whole frame: payloads are decoded here, then committed
  std::optional<uint64_t> newest_requested_;
  ReassemblerStats stats_;
};

}  // namespace dhr
