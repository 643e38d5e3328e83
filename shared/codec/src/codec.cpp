#include "codec/codec.hpp"

#include "protocol/byte_io.hpp"

#include <lz4.h>

#include <algorithm>
#include <cstring>

namespace dhr {
namespace {

constexpr size_t kUniformHeader = 5;  // kind + count, then the mask
constexpr size_t kLz4Header = 7;      // kind + count + compressed size
constexpr size_t kRawHeader = 5;      // kind + count
constexpr size_t kMinChunkRoom = 16;  // with less room left, a shard is closed
constexpr size_t kMaxShardsPerFrame = 65535;
// Per-shard slack used by codec_bound: room left unused when a shard closes plus a chunk header.
constexpr size_t kBoundSlackPerShard = 48;

size_t clamp_payload(size_t max_payload) { return std::clamp(max_payload, kMinShardPayload, kMaxShardPayload); }

// Host-order load of one mask, only ever compared for equality (so byte order does not matter).
template <class M>
M load(const uint8_t* data, size_t i) {
  M v;
  std::memcpy(&v, data + i * sizeof(M), sizeof(M));
  return v;
}

// First s in [from, n) where `run` equal masks start (the run may continue past any limit), or
// `fallback` once every candidate would start at or after `stop`.
template <class M>
size_t find_long_run_t(const uint8_t* data, size_t n, size_t from, size_t stop, size_t run, size_t fallback) {
  if (from >= n) return n;
  if (from >= stop) return fallback;
  size_t run_start = from;
  M prev = load<M>(data, from);
  for (size_t i = from + 1; i < n; ++i) {
    const M cur = load<M>(data, i);
    if (cur != prev) {
      prev = cur;
      run_start = i;
      if (run_start >= stop) return fallback;
    } else if (i + 1 - run_start >= run) {
      return run_start;
    }
  }
  return fallback;
}

template <class M>
size_t run_length_t(const uint8_t* data, size_t from, size_t limit) {
  const M first = load<M>(data, from);
  size_t i = from + 1;
  while (i < limit && load<M>(data, i) == first) ++i;
  return i - from;
}

class Encoder {
 public:
  Encoder(const VisibilityBuffer& buffer, const EncodeOptions& options)
      : data_(buffer.data.data()),
        n_(buffer.pixel_count()),
        mb_(buffer.bytes_per_mask()),
        width_(buffer.width),
        budget_(clamp_payload(options.max_payload)),
        // Rounded up without overflow: uniform_min_bytes may be SIZE_MAX ("never").
        run_px_(std::max<size_t>(2, std::max<size_t>(32, options.uniform_min_bytes) / mb_ +
                                        (std::max<size_t>(32, options.uniform_min_bytes) % mb_ != 0))),
        row_aligned_(options.row_aligned) {
    payload_.reserve(budget_);
    scratch_.resize(budget_);
  }

  bool run(std::vector<EncodedShard>& out, CodecStats& stats) {
    // A buffer of one mask (all lit, all dark, or a tiny one) is one uniform chunk whatever its size.
    next_run_ = run_length(0, n_) == n_ ? 0 : find_long_run(0, n_, n_);
    while (pos_ < n_) {
      payload_.clear();
      chunks_.clear();
      const size_t start = pos_;
      fill(n_);
      if (row_aligned_ && pos_ < n_ && pos_ % width_ != 0) {
        size_t row_floor = pos_ - pos_ % width_;
        if (row_floor > start) ++stats.row_trims;
        while (row_floor > start) {
          trim_to(row_floor);
          if (pos_ == row_floor) break;
          // Compressed on its own, the shorter input did not quite fit (LZ4 parses the end of a block
          // differently): give up one more row.
          row_floor -= width_;
        }
      }
      if (chunks_.empty() || out.size() >= kMaxShardsPerFrame) return false;  // no progress / too many shards
      for (const Chunk& c : chunks_) count_chunk(c, stats);
      EncodedShard& shard = out.emplace_back();
      shard.first_pixel = static_cast<uint32_t>(start);
      shard.pixel_count = static_cast<uint32_t>(pos_ - start);
      shard.payload = payload_;
      stats.payload_bytes += payload_.size();
    }
    return true;
  }

 private:
  struct Chunk {
    ChunkKind kind;
    size_t first;
    size_t count;
    size_t offset;  // in payload_
  };

  size_t find_long_run(size_t from, size_t stop, size_t fallback) const {
    switch (mb_) {
      case 1: return find_long_run_t<uint8_t>(data_, n_, from, stop, run_px_, fallback);
      case 2: return find_long_run_t<uint16_t>(data_, n_, from, stop, run_px_, fallback);
      default: return find_long_run_t<uint32_t>(data_, n_, from, stop, run_px_, fallback);
    }
  }

  size_t run_length(size_t from, size_t limit) const {
    switch (mb_) {
      case 1: return run_length_t<uint8_t>(data_, from, limit);
      case 2: return run_length_t<uint16_t>(data_, from, limit);
      default: return run_length_t<uint32_t>(data_, from, limit);
    }
  }

  // Appends chunks from pos_ until the shard budget is used up or pos_ reaches limit.
  // Invariant: next_run_ is the first s >= pos_ where a long run of equal masks starts (or n_).
  void fill(size_t limit) {
    while (pos_ < limit) {
      const size_t room = budget_ - payload_.size();
      if (pos_ == next_run_) {
        if (room < kUniformHeader + mb_) return;
        const size_t len = run_length(pos_, limit);
        begin_chunk(ChunkKind::kUniform, len);
        payload_.insert(payload_.end(), data_ + pos_ * mb_, data_ + (pos_ + 1) * mb_);
        pos_ += len;
        next_run_ = find_long_run(pos_, n_, n_);
        continue;
      }
      if (room < kMinChunkRoom) return;
      const size_t stretch = std::min(next_run_, limit) - pos_;
      size_t lz4_size = 0;
      const size_t lz4_px = compress(stretch, room - kLz4Header, lz4_size);
      const size_t raw_px = std::min(stretch, (room - kRawHeader) / mb_);
      const bool use_lz4 =
          lz4_px > raw_px || (lz4_px == raw_px && lz4_px > 0 && kLz4Header + lz4_size < kRawHeader + raw_px * mb_);
      const size_t px = use_lz4 ? lz4_px : raw_px;
      if (px == 0) return;
      if (use_lz4) {
        begin_chunk(ChunkKind::kLz4, px);
        payload_.push_back(static_cast<uint8_t>(lz4_size));
        payload_.push_back(static_cast<uint8_t>(lz4_size >> 8));
        payload_.insert(payload_.end(), scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(lz4_size));
      } else {
        begin_chunk(ChunkKind::kRaw, px);
        payload_.insert(payload_.end(), data_ + pos_ * mb_, data_ + (pos_ + px) * mb_);
      }
      pos_ += px;
      if (px < stretch) return;  // the shard is full
    }
  }

  void begin_chunk(ChunkKind kind, size_t count) {
    chunks_.push_back(Chunk{kind, pos_, count, payload_.size()});
    payload_.push_back(static_cast<uint8_t>(kind));
    for (int i = 0; i < 4; ++i) payload_.push_back(static_cast<uint8_t>(count >> (8 * i)));
  }

  // LZ4-compresses as many whole masks from pos_ (at most max_px) as fit in `cap` bytes, into scratch_.
  // Returns the mask count (0 if none fit) and the compressed size.
  size_t compress(size_t max_px, size_t cap, size_t& out_size) {
    const char* src = reinterpret_cast<const char*>(data_ + pos_ * mb_);
    char* dst = reinterpret_cast<char*>(scratch_.data());
    int src_size = static_cast<int>(max_px * mb_);
    int written = LZ4_compress_destSize(src, dst, &src_size, static_cast<int>(cap));
    if (written <= 0) return 0;
    size_t px = static_cast<size_t>(src_size) / mb_;
    if (static_cast<size_t>(src_size) % mb_ != 0) {
      // It stopped inside a mask: compress whole masks only (a shorter input practically always fits).
      written = 0;
      while (px > 0) {
        written = LZ4_compress_default(src, dst, static_cast<int>(px * mb_), static_cast<int>(cap));
        if (written > 0) break;
        px -= std::max<size_t>(1, px / 8);
      }
      if (written <= 0) return 0;
    }
    out_size = static_cast<size_t>(written);
    return px;
  }

  // Shortens the current shard to end at row_floor: drops the chunks from the one that crosses it and
  // re-encodes that stretch with row_floor as the limit.
  void trim_to(size_t row_floor) {
    size_t k = 0;
    while (k < chunks_.size() && chunks_[k].first + chunks_[k].count <= row_floor) ++k;
    if (k == chunks_.size()) return;
    const size_t old_pos = pos_;
    const size_t old_next_run = next_run_;
    pos_ = chunks_[k].first;
    payload_.resize(chunks_[k].offset);
    chunks_.resize(k);
    // Restore the invariant for the rewound position: a long run may start in [pos_, old_pos).
    next_run_ = find_long_run(pos_, old_pos, old_next_run);
    fill(row_floor);
  }

  static void count_chunk(const Chunk& c, CodecStats& stats) {
    switch (c.kind) {
      case ChunkKind::kUniform:
        ++stats.uniform_chunks;
        stats.uniform_pixels += c.count;
        break;
      case ChunkKind::kLz4:
        ++stats.lz4_chunks;
        stats.lz4_pixels += c.count;
        break;
      case ChunkKind::kRaw:
        ++stats.raw_chunks;
        stats.raw_pixels += c.count;
        break;
    }
  }

  const uint8_t* data_;
  size_t n_;
  uint32_t mb_;
  uint32_t width_;
  size_t budget_;
  size_t run_px_;
  bool row_aligned_;
  size_t pos_ = 0;
  size_t next_run_ = 0;
  std::vector<uint8_t> payload_;
  std::vector<uint8_t> scratch_;
  std::vector<Chunk> chunks_;
};

bool buffer_consistent(const VisibilityBuffer& b) {
  if (b.width < 1 || b.height < 1 || b.width > kMaxBufferDimension || b.height > kMaxBufferDimension) return false;
  if (b.light_count > kMaxLights) return false;
  if (!mask_width_from_bits(static_cast<uint32_t>(b.mask_bits))) return false;
  return b.data.size() == b.size_bytes();
}

}  // namespace

CodecBound codec_bound(uint32_t width, uint32_t height, MaskWidth mask_bits, size_t max_payload) {
  const size_t budget = clamp_payload(max_payload);
  const size_t bytes = static_cast<size_t>(width) * height * mask_bytes(mask_bits);
  CodecBound bound;
  // At most one shard per row boundary is cut short; every other shard but the last fills its budget
  // to within kBoundSlackPerShard bytes, and every chunk costs at most its raw size plus a header.
  const size_t per_shard = budget - kBoundSlackPerShard;
  bound.max_shards = height + (bytes + per_shard - 1) / per_shard + 1;
  bound.max_payload_bytes = std::min(bound.max_shards * budget, bytes + bound.max_shards * kBoundSlackPerShard);
  return bound;
}

bool encode_visibility(const VisibilityBuffer& buffer, const EncodeOptions& options,
                       std::vector<EncodedShard>& out_shards, CodecStats* out_stats) {
  out_shards.clear();
  CodecStats stats;
  if (!buffer_consistent(buffer)) return false;
  stats.raw_bytes = buffer.size_bytes();
  Encoder encoder(buffer, options);
  if (!encoder.run(out_shards, stats)) {
    out_shards.clear();
    return false;
  }
  stats.shard_count = out_shards.size();
  stats.datagram_bytes = stats.payload_bytes + stats.shard_count * kShardFixedSize;
  if (out_stats) *out_stats = stats;
  return true;
}

DecodeError decode_shard_payload(std::span<const uint8_t> payload, uint32_t first_pixel, uint32_t pixel_count,
                                 MaskWidth mask_bits, std::span<uint8_t> frame) {
  if (!mask_width_from_bits(static_cast<uint32_t>(mask_bits))) return DecodeError::kBadValue;
  const size_t mb = mask_bytes(mask_bits);
  const size_t total = frame.size() / mb;
  if (frame.size() % mb != 0 || pixel_count == 0 || uint64_t{first_pixel} + pixel_count > total)
    return DecodeError::kBadValue;
  size_t pos = first_pixel;
  const size_t end = size_t{first_pixel} + pixel_count;
  ByteReader r(payload);
  while (!r.at_end()) {
    const uint8_t kind = r.u8();
    const uint32_t count = r.u32();
    if (!r.ok() || count == 0 || count > end - pos) return DecodeError::kBadPayload;
    uint8_t* dst = frame.data() + pos * mb;
    const size_t out_bytes = size_t{count} * mb;
    switch (static_cast<ChunkKind>(kind)) {
      case ChunkKind::kUniform: {
        const auto mask = r.bytes(mb);
        if (!r.ok()) return DecodeError::kBadPayload;
        for (size_t i = 0; i < count; ++i)
          for (size_t j = 0; j < mb; ++j) dst[i * mb + j] = mask[j];
        break;
      }
      case ChunkKind::kLz4: {
        const uint16_t size = r.u16();
        const auto src = r.bytes(size);
        if (!r.ok() || size == 0) return DecodeError::kBadPayload;
        const int got = LZ4_decompress_safe(reinterpret_cast<const char*>(src.data()), reinterpret_cast<char*>(dst),
                                            static_cast<int>(size), static_cast<int>(out_bytes));
        if (got < 0 || static_cast<size_t>(got) != out_bytes) return DecodeError::kBadPayload;
        break;
      }
      case ChunkKind::kRaw: {
        const auto src = r.bytes(out_bytes);
        if (!r.ok()) return DecodeError::kBadPayload;
        std::memcpy(dst, src.data(), out_bytes);
        break;
      }
      default: return DecodeError::kBadPayload;
    }
    pos += count;
  }
  return pos == end ? DecodeError::kNone : DecodeError::kBadPayload;
}

size_t whole_frame_lz4_size(std::span<const uint8_t> bytes) {
  if (bytes.size() > static_cast<size_t>(LZ4_MAX_INPUT_SIZE)) return 0;
  std::vector<char> out(static_cast<size_t>(LZ4_compressBound(static_cast<int>(bytes.size()))));
  const int n = LZ4_compress_default(reinterpret_cast<const char*>(bytes.data()), out.data(),
                                     static_cast<int>(bytes.size()), static_cast<int>(out.size()));
  return n > 0 ? static_cast<size_t>(n) : 0;
}

std::vector<VisibilityShard> shards_as_messages(const VisibilityBuffer& buffer, uint64_t frame_number, Eye eye,
                                                const View& view, const std::vector<EncodedShard>& encoded) {
  std::vector<VisibilityShard> shards(encoded.size());
  for (size_t i = 0; i < encoded.size(); ++i) {
    VisibilityShard& s = shards[i];
    s.frame_number = frame_number;
    s.eye = eye;
    s.mask_bits = buffer.mask_bits;
    s.shard_index = static_cast<uint16_t>(i);
    s.shard_count = static_cast<uint16_t>(encoded.size());
    s.buffer_width = static_cast<uint16_t>(buffer.width);
    s.buffer_height = static_cast<uint16_t>(buffer.height);
    s.first_pixel = encoded[i].first_pixel;
    s.pixel_count = encoded[i].pixel_count;
    s.view = view;
    s.payload_size = static_cast<uint16_t>(encoded[i].payload.size());
    std::copy(encoded[i].payload.begin(), encoded[i].payload.end(), s.payload.begin());
  }
  return shards;
}

std::vector<VisibilityShard> make_visibility_shards(const VisibilityBuffer& buffer, uint64_t frame_number, Eye eye,
                                                    const View& view, const EncodeOptions& options,
                                                    CodecStats* out_stats) {
  std::vector<EncodedShard> encoded;
  if (!encode_visibility(buffer, options, encoded, out_stats)) return {};
  return shards_as_messages(buffer, frame_number, eye, view, encoded);
}

}  // namespace dhr
