#include "codec/reassembly.hpp"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <string>

namespace dhr {
namespace {

bool same_view(const View& a, const View& b) {
  return a.pose.position == b.pose.position && a.pose.orientation == b.pose.orientation &&
         a.fov.angle_left == b.fov.angle_left && a.fov.angle_right == b.fov.angle_right &&
         a.fov.angle_up == b.fov.angle_up && a.fov.angle_down == b.fov.angle_down;
}

}  // namespace

const char* to_string(InsertStatus status) {
  switch (status) {
    case InsertStatus::kAccepted: return "accepted";
    case InsertStatus::kCompleted: return "completed";
    case InsertStatus::kDuplicate: return "duplicate";
    case InsertStatus::kLate: return "late";
    case InsertStatus::kRejected: return "rejected";
  }
  return "unknown";
}

VisibilityReassembler::VisibilityReassembler(const ReassemblerConfig& config)
    : config_(config), mask_bits_(mask_width_for_light_count(config.light_count)) {
  if (config.width < 1 || config.height < 1 || config.width > kMaxBufferDimension ||
      config.height > kMaxBufferDimension)
    throw std::invalid_argument("reassembler: bad buffer size " + std::to_string(config.width) + "x" +
                                std::to_string(config.height));
  if (config.light_count > kMaxLights)
    throw std::invalid_argument("reassembler: " + std::to_string(config.light_count) + " lights");
  if (config.max_frames_in_flight < 2 || config.max_frames_in_flight > 64)
    throw std::invalid_argument("reassembler: max_frames_in_flight must be in 2..64");
  if (config.reference_frames > 64) throw std::invalid_argument("reassembler: reference_frames must be in 0..64");
  max_shards_ = std::min<size_t>(65535, codec_bound(config.width, config.height, mask_bits_, config.max_payload).max_shards);
  for (EyeState& eye : eyes_) eye.slots.resize(config.max_frames_in_flight);
}

InsertResult VisibilityReassembler::reject(DecodeError error) {
  ++stats_.shards_rejected;
  stats_.rejections.add(error);
  return InsertResult{InsertStatus::kRejected, error};
}

VisibilityReassembler::Slot* VisibilityReassembler::find_slot(EyeState& eye, uint64_t frame) {
  for (Slot& s : eye.slots)
    if (s.in_use && s.frame.visibility.frame_number == frame) return &s;
  return nullptr;
}

VisibilityReassembler::Slot* VisibilityReassembler::claim_slot(EyeState& eye, uint64_t frame, bool& out_late) {
  out_late = false;
  Slot* oldest = nullptr;  // oldest incomplete frame: the eviction candidate
  for (Slot& s : eye.slots) {
    if (!s.in_use) return &s;
    if (eye.complete_frame && s.frame.visibility.frame_number == *eye.complete_frame) continue;
    if (!oldest || s.frame.visibility.frame_number < oldest->frame.visibility.frame_number) oldest = &s;
  }
  if (!oldest || frame < oldest->frame.visibility.frame_number) {
    out_late = true;
    return nullptr;
  }
  ++stats_.frames_evicted;
  oldest->in_use = false;
  return oldest;
}

void VisibilityReassembler::start_frame(Slot& slot, const VisibilityShard& shard) {
  if (!slot.allocated) {
    slot.frame.visibility.buffer = VisibilityBuffer::create(config_.width, config_.height, config_.light_count);
    slot.frame.visibility.row_valid.assign(config_.height, 0);
    slot.row_pixels.assign(config_.height, 0);
    slot.shard_received.reserve(max_shards_);
    slot.frame.received_ranges.reserve(64);
    slot.allocated = true;
  } else {
    std::fill(slot.frame.visibility.buffer.data.begin(), slot.frame.visibility.buffer.data.end(), uint8_t{0});
    std::fill(slot.frame.visibility.row_valid.begin(), slot.frame.visibility.row_valid.end(), uint8_t{0});
    std::fill(slot.row_pixels.begin(), slot.row_pixels.end(), 0u);
  }
  slot.in_use = true;
  slot.frame.visibility.frame_number = shard.frame_number;
  slot.frame.visibility.eye = shard.eye;
  slot.frame.visibility.view = shard.view;
  slot.frame.visibility.scene_time_ns = shard.scene_time_ns;
  slot.frame.visibility.rows_valid = 0;
  slot.frame.visibility.complete = false;
  slot.frame.pixels_received = 0;
  slot.frame.shard_count = shard.shard_count;
  slot.frame.shards_received = 0;
  slot.shard_received.assign(shard.shard_count, 0);
  slot.frame.received_ranges.clear();
  ++stats_.frames_started;
}

void VisibilityReassembler::commit(Slot& slot, const VisibilityShard& shard) {
  const size_t mb = mask_bytes(mask_bits_);
  const size_t first = shard.first_pixel, end = first + shard.pixel_count;
  std::memcpy(slot.frame.visibility.buffer.data.data() + first * mb, scratch_.data() + first * mb, (end - first) * mb);
  slot.shard_received[shard.shard_index] = 1;
  const auto range = std::make_pair(shard.first_pixel, static_cast<uint32_t>(end));
  auto& ranges = slot.frame.received_ranges;
  ranges.insert(std::lower_bound(ranges.begin(), ranges.end(), range), range);
  const size_t w = config_.width;
  for (size_t y = first / w; y <= (end - 1) / w; ++y) {
    const size_t row_begin = y * w, row_end = row_begin + w;
    slot.row_pixels[y] += static_cast<uint32_t>(std::min(end, row_end) - std::max(first, row_begin));
    if (slot.row_pixels[y] == w) {
      slot.frame.visibility.row_valid[y] = 1;
      ++slot.frame.visibility.rows_valid;
    }
  }
  slot.frame.pixels_received += shard.pixel_count;
  ++slot.frame.shards_received;
}

void VisibilityReassembler::release_older(EyeState& eye, uint64_t frame) {
  for (Slot& s : eye.slots) {
    if (!s.in_use || s.frame.visibility.frame_number >= frame) continue;
    if (!s.frame.complete()) ++stats_.frames_superseded;
    s.in_use = false;
  }
}

const VisibilityBuffer* VisibilityReassembler::find_reference(const EyeState& eye, uint64_t frame) const {
  for (size_t i = 0; i < eye.references_used; ++i)
    if (eye.references[i].frame == frame) return &eye.references[i].buffer;
  return nullptr;
}

void VisibilityReassembler::keep_reference(EyeState& eye, const ReassembledFrame& frame) {
  if (config_.reference_frames == 0) return;
  if (eye.references.size() < config_.reference_frames) eye.references.resize(config_.reference_frames);
  Reference& r = eye.references[eye.next_reference];
  r.frame = frame.visibility.frame_number;
  r.buffer = frame.visibility.buffer;  // recycled storage after the ring's first round: no allocation
  eye.next_reference = (eye.next_reference + 1) % config_.reference_frames;
  eye.references_used = std::min(eye.references_used + 1, config_.reference_frames);
}

std::optional<uint64_t> VisibilityReassembler::newest_reference(Eye eye) const {
  const EyeState& e = eyes_[static_cast<size_t>(eye) & 1u];
  if (e.references_used == 0) return std::nullopt;
  uint64_t newest = 0;
  for (size_t i = 0; i < e.references_used; ++i) newest = std::max(newest, e.references[i].frame);
  return newest;
}

InsertResult VisibilityReassembler::insert(const VisibilityShard& shard) {
  // Session checks: a shard may come from the wire decoder or be built in-process, so check everything.
  const uint8_t eye_index = static_cast<uint8_t>(shard.eye);
  if (eye_index > 1 || shard.shard_count < 1 || shard.shard_index >= shard.shard_count ||
      shard.payload_size < 1 || shard.payload_size > kMaxShardPayload || shard.pixel_count < 1 ||
      shard.scene_time_ns < 0)
    return reject(DecodeError::kBadValue);
  if (shard.buffer_width != config_.width || shard.buffer_height != config_.height ||
      shard.mask_bits != mask_bits_ || shard.shard_count > max_shards_)
    return reject(DecodeError::kSessionMismatch);
  const uint64_t total = uint64_t{config_.width} * config_.height;
  if (uint64_t{shard.first_pixel} + shard.pixel_count > total) return reject(DecodeError::kBadValue);
  if (newest_requested_ && shard.frame_number > *newest_requested_) return reject(DecodeError::kFutureFrame);

  EyeState& eye = eyes_[eye_index];
  if (eye.complete_frame && shard.frame_number <= *eye.complete_frame) {
    if (shard.frame_number == *eye.complete_frame) {
      ++stats_.shards_duplicate;
      return InsertResult{InsertStatus::kDuplicate};
    }
    ++stats_.shards_late;
    return InsertResult{InsertStatus::kLate};
  }

  Slot* slot = find_slot(eye, shard.frame_number);
  if (slot) {
    if (shard.shard_count != slot->frame.shard_count || !same_view(shard.view, slot->frame.visibility.view) ||
        shard.scene_time_ns != slot->frame.visibility.scene_time_ns)
      return reject(DecodeError::kInconsistentFrame);
    if (slot->shard_received[shard.shard_index]) {
      ++stats_.shards_duplicate;
      return InsertResult{InsertStatus::kDuplicate};
    }
    const uint32_t first = shard.first_pixel, end = first + shard.pixel_count;
    const auto& ranges = slot->frame.received_ranges;
    auto it = std::lower_bound(ranges.begin(), ranges.end(), std::make_pair(first, end));
    if ((it != ranges.end() && it->first < end) || (it != ranges.begin() && std::prev(it)->second > first))
      return reject(DecodeError::kInconsistentFrame);
  } else {
    // A frame we will not keep is dropped before its payload is even decoded.
    bool late = false;
    const bool have_free = std::any_of(eye.slots.begin(), eye.slots.end(), [](const Slot& s) { return !s.in_use; });
    if (!have_free) {
      uint64_t oldest = UINT64_MAX;
      for (const Slot& s : eye.slots)
        if (!(eye.complete_frame && s.frame.visibility.frame_number == *eye.complete_frame))
          oldest = std::min(oldest, s.frame.visibility.frame_number);
      late = oldest == UINT64_MAX || shard.frame_number < oldest;
    }
    if (late) {
      ++stats_.shards_late;
      return InsertResult{InsertStatus::kLate};
    }
  }

  if (scratch_.empty()) scratch_.resize(static_cast<size_t>(total) * mask_bytes(mask_bits_));
  DecodeError e;
  if (is_v2_payload(shard.payload_bytes())) {
    // Inter shards decode only against the exact frame they name; a frame not held is never substituted.
    const std::optional<uint64_t> need = v2_reference_frame(shard.payload_bytes(), shard.frame_number);
    const VisibilityBuffer* reference = need ? find_reference(eye, *need) : nullptr;
    if (need && reference == nullptr) return reject(DecodeError::kMissingReference);
    e = decode_shard_payload_v2(shard.payload_bytes(), shard.first_pixel, shard.pixel_count, config_.width,
                                config_.height, config_.light_count, reference, scratch_);
  } else {
    e = decode_shard_payload(shard.payload_bytes(), shard.first_pixel, shard.pixel_count, mask_bits_, scratch_);
  }
  if (e != DecodeError::kNone) return reject(e);

  if (!slot) {
    bool late = false;
    slot = claim_slot(eye, shard.frame_number, late);
    if (!slot) {  // cannot happen after the check above; kept so a logic slip drops instead of crashing
      ++stats_.shards_late;
      return InsertResult{InsertStatus::kLate};
    }
    start_frame(*slot, shard);
  }
  commit(*slot, shard);
  ++stats_.shards_accepted;
  if (!slot->frame.complete()) return InsertResult{InsertStatus::kAccepted};
  slot->frame.visibility.complete = true;
  ++stats_.frames_completed;
  eye.complete_frame = shard.frame_number;
  keep_reference(eye, slot->frame);
  release_older(eye, shard.frame_number);
  return InsertResult{InsertStatus::kCompleted};
}

const ReassembledFrame* VisibilityReassembler::latest(Eye eye) const {
  const auto index = static_cast<size_t>(eye);
  if (index > 1) return nullptr;
  const ReassembledFrame* best = nullptr;
  for (const Slot& s : eyes_[index].slots)
    if (s.in_use && (!best || s.frame.visibility.frame_number > best->visibility.frame_number)) best = &s.frame;
  return best;
}

const ReassembledFrame* VisibilityReassembler::latest_complete(Eye eye) const {
  const auto index = static_cast<size_t>(eye);
  if (index > 1 || !eyes_[index].complete_frame) return nullptr;
  for (const Slot& s : eyes_[index].slots)
    if (s.in_use && s.frame.visibility.frame_number == *eyes_[index].complete_frame) return &s.frame;
  return nullptr;
}

size_t VisibilityReassembler::memory_bytes() const {
  size_t bytes = scratch_.capacity();
  for (const EyeState& eye : eyes_)
    for (const Slot& s : eye.slots)
      bytes += s.frame.visibility.buffer.data.capacity() + s.frame.visibility.row_valid.capacity() + s.row_pixels.capacity() * 4 +
               s.shard_received.capacity() + s.frame.received_ranges.capacity() * sizeof(s.frame.received_ranges[0]);
  for (const EyeState& eye : eyes_)
    for (const Reference& r : eye.references) bytes += r.buffer.data.capacity();
  return bytes;
}

void VisibilityReassembler::reset() {
  for (EyeState& eye : eyes_) {
    for (Slot& s : eye.slots) s.in_use = false;
    eye.complete_frame.reset();
    eye.references_used = 0;  // a new session's frames never decode against an old one's
    eye.next_reference = 0;
  }
}

}  // namespace dhr
