#include "codec_measure.hpp"

#include <lz4.h>

#include <algorithm>
#include <chrono>
#include <functional>

namespace dhr::bench {
namespace {

using Clock = std::chrono::steady_clock;

// Runs `body` `repeat` times; MB/s of `bytes` per run at the median and the best run.
Rate time_rate(int repeat, size_t bytes, const std::function<void()>& body) {
  std::vector<double> seconds;
  for (int i = 0; i < repeat; ++i) {
    const auto start = Clock::now();
    body();
    seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  const double median = seconds[seconds.size() / 2];
  Rate r;
  r.median_mb_s = median > 0.0 ? static_cast<double>(bytes) / median / 1e6 : 0.0;
  r.best_mb_s = seconds.front() > 0.0 ? static_cast<double>(bytes) / seconds.front() / 1e6 : 0.0;
  return r;
}

SizeStats size_stats(const std::vector<size_t>& values) {
  SizeStats s;
  if (values.empty()) return s;
  double sum = 0.0;
  s.min = values.front();
  s.max = values.front();
  for (size_t v : values) {
    sum += static_cast<double>(v);
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
  }
  s.mean = sum / static_cast<double>(values.size());
  return s;
}

}  // namespace

CodecMeasurement measure_codec(const BufferSet& set, int repeat) {
  CodecMeasurement m;
  m.buffers = set.buffers.size();
  if (set.buffers.empty()) return m;
  repeat = std::max(repeat, 1);
  m.raw_bytes_per_buffer = set.buffers.front().size_bytes();
  size_t raw_total = 0;
  for (const VisibilityBuffer& b : set.buffers) raw_total += b.size_bytes();

  // Sizes (and the shards the decoder is timed on).
  const EncodeOptions options;
  EncodeOptions aligned;
  aligned.row_aligned = true;
  std::vector<std::vector<EncodedShard>> encoded(set.buffers.size());
  std::vector<size_t> payload, datagram, shards, whole, row_aligned;
  size_t uniform_pixels = 0, pixels = 0;
  for (size_t i = 0; i < set.buffers.size(); ++i) {
    const VisibilityBuffer& b = set.buffers[i];
    CodecStats stats;
    if (!encode_visibility(b, options, encoded[i], &stats)) {
      m.round_trip_ok = false;
      continue;
    }
    payload.push_back(stats.payload_bytes);
    datagram.push_back(stats.datagram_bytes);
    shards.push_back(stats.shard_count);
    whole.push_back(whole_frame_lz4_size(b.data));
    uniform_pixels += stats.uniform_pixels;
    pixels += b.pixel_count();
    std::vector<EncodedShard> tmp;
    CodecStats aligned_stats;
    if (encode_visibility(b, aligned, tmp, &aligned_stats)) row_aligned.push_back(aligned_stats.payload_bytes);
  }
  m.payload_bytes = size_stats(payload);
  m.datagram_bytes = size_stats(datagram);
  m.shards = size_stats(shards);
  m.whole_frame_lz4_bytes = size_stats(whole);
  m.row_aligned_payload_bytes = size_stats(row_aligned);
  m.uniform_pixel_fraction = pixels ? static_cast<double>(uniform_pixels) / static_cast<double>(pixels) : 0.0;

  std::vector<EncodedShard> scratch;
  m.encode = time_rate(repeat, raw_total, [&] {
    for (const VisibilityBuffer& b : set.buffers) encode_visibility(b, options, scratch);
  });

  std::vector<std::vector<uint8_t>> frames;
  for (const VisibilityBuffer& b : set.buffers) frames.emplace_back(b.data.size(), 0);
  m.decode = time_rate(repeat, raw_total, [&] {
    for (size_t i = 0; i < set.buffers.size(); ++i)
      for (const EncodedShard& s : encoded[i])
        if (decode_shard_payload(s.payload, s.first_pixel, s.pixel_count, set.buffers[i].mask_bits, frames[i]) !=
            DecodeError::kNone)
          m.round_trip_ok = false;
  });
  for (size_t i = 0; i < set.buffers.size(); ++i)
    if (frames[i] != set.buffers[i].data) m.round_trip_ok = false;

  // Whole-frame LZ4 in this process, on the same bytes.
  std::vector<std::vector<char>> compressed(set.buffers.size());
  std::vector<int> compressed_size(set.buffers.size(), 0);
  for (size_t i = 0; i < set.buffers.size(); ++i)
    compressed[i].resize(static_cast<size_t>(LZ4_compressBound(static_cast<int>(set.buffers[i].data.size()))));
  m.lz4_frame_compress = time_rate(repeat, raw_total, [&] {
    for (size_t i = 0; i < set.buffers.size(); ++i) {
      const auto& src = set.buffers[i].data;
      compressed_size[i] = LZ4_compress_default(reinterpret_cast<const char*>(src.data()), compressed[i].data(),
                                                static_cast<int>(src.size()), static_cast<int>(compressed[i].size()));
    }
  });
  m.lz4_frame_decompress = time_rate(repeat, raw_total, [&] {
    for (size_t i = 0; i < set.buffers.size(); ++i) {
      const int got = LZ4_decompress_safe(compressed[i].data(), reinterpret_cast<char*>(frames[i].data()),
                                          compressed_size[i], static_cast<int>(frames[i].size()));
      if (got != static_cast<int>(frames[i].size())) m.round_trip_ok = false;
    }
  });
  return m;
}

}  // namespace dhr::bench
