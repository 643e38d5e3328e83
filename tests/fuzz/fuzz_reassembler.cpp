// Fuzz target: VisibilityReassembler fed a sequence of shards carved from the input: real shards of
// synthetic frames (any frame order, eye, duplicates, loss) mixed with forged ones (fields and payload
// from the input), resets and newest-requested-frame changes. See ReassemblerParams / ReassemblerOp.
// Properties after every operation: no crash or sanitizer report; memory_bytes() within a fixed bound
// computed from the configuration; per eye the newest complete frame never goes back (until reset()) and
// latest() is at least as new; each held frame's bookkeeping is consistent (sorted disjoint ranges that
// sum to pixels_received, row_valid exactly the fully covered rows); frames built from real shards hold
// exactly the real masks in every received range; insert()'s status agrees with the statistics.
#include "codec/codec.hpp"
#include "codec/reassembly.hpp"
#include "fuzz_layouts.hpp"
#include "fuzz_support.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

namespace {

using namespace dhr;
using fuzz::ReassemblerOp;
using fuzz::ReassemblerParams;

struct RealFrame {
  VisibilityBuffer buffer;
  std::vector<VisibilityShard> shards;
};

// Cheap frame contents that differ per (frame, eye): blocky lit/unlit areas, whole uniform rows (long
// runs) and hashed noise, so the encoder uses every chunk kind.
VisibilityBuffer real_buffer(const ReassemblerParams& p, uint64_t frame, Eye eye) {
  VisibilityBuffer b = VisibilityBuffer::create(p.width, p.height, p.light_count);
  const uint32_t bits = b.light_bits();
  const uint64_t e = static_cast<uint64_t>(eye);
  for (uint32_t y = 0; y < p.height; ++y)
    for (uint32_t x = 0; x < p.width; ++x) {
      uint32_t mask;
      if (y % 7 == (frame + e) % 7) {
        mask = bits;
      } else if (((x + 3 * frame) / 5 + (y + e) / 3) % 4 == 0) {
        mask = 0;
      } else {
        uint64_t h = (uint64_t{x} * 0x9E3779B1u) ^ (uint64_t{y} * 0x85EBCA77u) ^ (frame * 0xC2B2AE3Du) ^ (e << 40);
        h ^= h >> 17;
        mask = static_cast<uint32_t>(h) & bits;
      }
      b.set(x, y, mask);
    }
  return b;
}

// Real frames: content and view depend only on (frame, eye); a real view has position.x == 0, a forged
// one never does, so a frame holding the real view was built from real shards only. The cache outlives
// one input (a pure function of its key, so results do not depend on what ran before) and is bounded.
class RealFrames {
 public:
  explicit RealFrames(const ReassemblerParams& p) : p_(p) {}
  const RealFrame& get(uint64_t frame, Eye eye) {
    const Key key{p_.width, p_.height, p_.light_count, p_.max_payload, frame, static_cast<uint32_t>(eye)};
    auto it = cache().find(key);
    if (it != cache().end()) return it->second;
    if (cache().size() >= 512) cache().clear();
    RealFrame f;
    f.buffer = real_buffer(p_, frame, eye);
    EncodeOptions options;
    options.max_payload = p_.max_payload;
    f.shards = make_visibility_shards(f.buffer, frame, eye, view(frame), options);
    DHR_FUZZ_CHECK(!f.shards.empty());
    return cache().emplace(key, std::move(f)).first->second;
  }
  static View view(uint64_t frame) {
    View v;
    v.pose.position = {0.0, 1.6, 0.001 * static_cast<double>(frame)};
    return v;
  }

 private:
  using Key = std::tuple<uint32_t, uint32_t, uint32_t, uint32_t, uint64_t, uint32_t>;
  static std::map<Key, RealFrame>& cache() {
    static std::map<Key, RealFrame> frames;
    return frames;
  }
  ReassemblerParams p_;
};

VisibilityShard forged_shard(fuzz::Reader& r, const ReassemblerParams& p, RealFrames& real) {
  const uint8_t flags = r.u8();
  VisibilityShard s;
  s.frame_number = r.u8();
  s.eye = static_cast<Eye>(r.u8() % 3);  // 2 is invalid on purpose
  const RealFrame& donor = real.get(s.frame_number, static_cast<Eye>(static_cast<uint8_t>(s.eye) & 1));
  const VisibilityShard& base = donor.shards[r.u16() % donor.shards.size()];
  s.view.pose.position = {1.0 + r.u8(), 1.6, 0.0};
  if (flags & 1) {
    s.buffer_width = r.u16();
    s.buffer_height = r.u16();
  } else {
    s.buffer_width = static_cast<uint16_t>(p.width);
    s.buffer_height = static_cast<uint16_t>(p.height);
  }
  s.mask_bits = (flags & 2) ? static_cast<MaskWidth>(r.u8()) : mask_width_for_light_count(p.light_count);
  if (flags & 4) {
    s.shard_index = r.u16();
    s.shard_count = r.u16();
    s.first_pixel = r.u32();
    s.pixel_count = r.u32();
  } else {
    s.shard_count = base.shard_count;
    s.shard_index = static_cast<uint16_t>(r.u16() % s.shard_count);
    const uint32_t total = p.width * p.height;
    s.first_pixel = r.u32() % total;
    s.pixel_count = 1 + r.u32() % (total - s.first_pixel);
  }
  if (flags & 8) {  // a real payload with one byte changed, at the real shard's region or the one above
    std::copy(base.payload.begin(), base.payload.end(), s.payload.begin());
    s.payload_size = base.payload_size;
    if (!(flags & 4)) {
      s.first_pixel = base.first_pixel;
      s.pixel_count = base.pixel_count;
    }
    const uint16_t at = r.u16();
    s.payload[at % s.payload_size] ^= r.u8();
  } else {
    const auto bytes = r.take(r.u16() % (kMaxShardPayload + 1));
    std::copy(bytes.begin(), bytes.end(), s.payload.begin());
    s.payload_size = static_cast<uint16_t>(bytes.size());
  }
  if (flags & 16) s.payload_size = r.u16();  // possibly above kMaxShardPayload: must be rejected, not read
  // Another scene time than the frame's other shards (inconsistent), or a negative one (invalid).
  if (flags & 32) s.scene_time_ns = static_cast<int8_t>(r.u8());
  return s;
}

void check_frame(const ReassembledFrame& f, const ReassemblerParams& p, RealFrames& real) {
  const size_t n = size_t{p.width} * p.height;
  DHR_FUZZ_CHECK(f.visibility.buffer.width == p.width && f.visibility.buffer.height == p.height && f.visibility.buffer.pixel_count() == n);
  DHR_FUZZ_CHECK(f.visibility.buffer.data.size() == f.visibility.buffer.size_bytes());
  DHR_FUZZ_CHECK(f.shards_received >= 1 && f.shards_received <= f.shard_count);
  size_t sum = 0, prev_end = 0;
  std::vector<uint32_t> row_pixels(p.height, 0);
  for (const auto& [first, end] : f.received_ranges) {
    DHR_FUZZ_CHECK_MSG(first >= prev_end && first < end && end <= n, "received ranges not sorted and disjoint");
    prev_end = end;
    sum += end - first;
    for (size_t i = first; i < end; ++i) ++row_pixels[i / p.width];
  }
  DHR_FUZZ_CHECK_MSG(sum == f.pixels_received, "received ranges do not add up to pixels_received");
  DHR_FUZZ_CHECK(f.complete() == (sum == n));
  uint32_t rows = 0;
  for (uint32_t y = 0; y < p.height; ++y) {
    const bool full = row_pixels[y] == p.width;
    DHR_FUZZ_CHECK_MSG((f.visibility.row_valid[y] != 0) == full, "row_valid disagrees with the received ranges");
    rows += full ? 1 : 0;
  }
  DHR_FUZZ_CHECK(f.visibility.rows_valid == rows);
  DHR_FUZZ_CHECK_MSG(f.visibility.scene_time_ns >= 0, "a frame holds a negative scene time");
  if (f.visibility.view.pose.position.x != 0.0) return;  // forged frame: contents are whatever was sent
  DHR_FUZZ_CHECK_MSG(f.visibility.scene_time_ns == 0, "a real frame holds another scene time than was sent");
  const VisibilityBuffer& truth = real.get(f.visibility.frame_number, f.visibility.eye).buffer;
  const size_t mb = truth.bytes_per_mask();
  for (const auto& [first, end] : f.received_ranges)
    DHR_FUZZ_CHECK_MSG(std::memcmp(f.visibility.buffer.data.data() + first * mb, truth.data.data() + first * mb,
                                   (end - first) * mb) == 0,
                       "a real frame holds other masks than were sent");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::Reader r(data, size);
  const ReassemblerParams p = ReassemblerParams::read(r);
  ReassemblerConfig config;
  config.width = p.width;
  config.height = p.height;
  config.light_count = p.light_count;
  config.max_frames_in_flight = p.frames_in_flight;
  config.max_payload = p.max_payload;
  VisibilityReassembler reassembler(config);
  if (p.limit_frames) reassembler.set_newest_requested_frame(p.newest_requested);
  RealFrames real(p);

  // Fixed by the configuration (see reassembly.hpp): scratch plus per eye and slot one buffer and its
  // bookkeeping, whose vectors are sized by the row count and the shard-count bound.
  const size_t frame_bytes = size_t{p.width} * p.height * mask_bytes(mask_width_for_light_count(p.light_count));
  const size_t shards = reassembler.max_shards_per_frame();
  const size_t per_slot = frame_bytes + 5 * size_t{p.height} + shards + 2 * std::max<size_t>(64, shards) * 8;
  const size_t memory_bound = frame_bytes + 2 * p.frames_in_flight * per_slot;

  std::optional<VisibilityShard> previous;
  std::optional<uint64_t> newest_complete[2];
  uint64_t inserts = 0;
  for (int ops = 0; !r.at_end() && ops < 2000; ++ops) {
    const uint8_t op = r.u8();
    std::optional<VisibilityShard> shard;
    switch (static_cast<ReassemblerOp>(op & 3)) {
      case ReassemblerOp::kGenuine:
      case ReassemblerOp::kGenuine2: {
        const uint64_t frame = r.u8();
        const Eye eye = static_cast<Eye>(r.u8() & 1);
        const RealFrame& f = real.get(frame, eye);
        shard = f.shards[r.u16() % f.shards.size()];
        break;
      }
      case ReassemblerOp::kForged: shard = forged_shard(r, p, real); break;
      case ReassemblerOp::kControl:
        switch ((op >> 2) % 3) {
          case 0:
            reassembler.reset();
            newest_complete[0].reset();
            newest_complete[1].reset();
            DHR_FUZZ_CHECK(!reassembler.latest(Eye::kLeft) && !reassembler.latest(Eye::kRight));
            break;
          case 1: shard = previous; break;
          default: reassembler.set_newest_requested_frame(r.u8()); break;
        }
        break;
    }
    if (shard) {
      const InsertResult result = reassembler.insert(*shard);
      ++inserts;
      previous = shard;
      DHR_FUZZ_CHECK((result.status == InsertStatus::kRejected) == (result.error != DecodeError::kNone));
      if (result.status == InsertStatus::kCompleted) {
        const ReassembledFrame* done = reassembler.latest_complete(shard->eye);
        DHR_FUZZ_CHECK_MSG(done && done->visibility.frame_number == shard->frame_number && done->complete(),
                           "kCompleted but the frame is not the newest complete one");
      }
    }
    const ReassemblerStats& st = reassembler.stats();
    DHR_FUZZ_CHECK_MSG(st.shards_accepted + st.shards_duplicate + st.shards_late + st.shards_rejected == inserts,
                       "statistics do not add up to the inserts");
    DHR_FUZZ_CHECK(st.rejections.total_errors() == st.shards_rejected);
    DHR_FUZZ_CHECK_MSG(reassembler.memory_bytes() <= memory_bound, "memory above the configured bound");
    for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
      const ReassembledFrame* complete = reassembler.latest_complete(eye);
      const ReassembledFrame* latest = reassembler.latest(eye);
      auto& newest = newest_complete[static_cast<int>(eye)];
      if (newest) {
        DHR_FUZZ_CHECK_MSG(complete != nullptr, "the newest complete frame disappeared");
        DHR_FUZZ_CHECK_MSG(complete->visibility.frame_number >= *newest, "the newest complete frame went back");
      }
      if (complete) {
        newest = complete->visibility.frame_number;
        DHR_FUZZ_CHECK(complete->complete() && complete->visibility.eye == eye);
        DHR_FUZZ_CHECK(latest && latest->visibility.frame_number >= complete->visibility.frame_number);
        check_frame(*complete, p, real);
      }
      if (latest) {
        DHR_FUZZ_CHECK(latest->visibility.eye == eye);
        if (latest != complete) check_frame(*latest, p, real);
      }
    }
  }
  return 0;
}
