// Measurements of the visibility codec on a set of buffers (bench/codec_bench): encode/decode speed of
// the sharded scheme, compressed sizes beside whole-frame LZ4, and the bit rate at 90 Hz stereo.
#pragma once
#include "codec/codec.hpp"
#include "visibility/visibility.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace dhr::bench {

struct BufferSet {
  std::string name;    // "traced" or "synthetic"
  std::string source;  // scene path + camera bookmarks, or the generator
  std::vector<std::string> labels;  // one per buffer, e.g. "doorway_overview/left"
  std::vector<VisibilityBuffer> buffers;
  double trace_ms_mean = -1.0;      // per eye buffer, -1 when not traced
  std::string tracer;               // tracer device description, empty when synthetic
};

struct Rate {
  double median_mb_s = 0.0;  // MB = 1e6 bytes of raw masks, over the median repetition
  double best_mb_s = 0.0;
};

struct SizeStats {
  double mean = 0.0;
  size_t min = 0;
  size_t max = 0;
};

struct CodecMeasurement {
  size_t buffers = 0;
  size_t raw_bytes_per_buffer = 0;  // of the first buffer (all share the size)
  Rate encode;                      // encode_visibility, one thread
  Rate decode;                      // decode_shard_payload of every shard, one thread
  Rate lz4_frame_compress;          // LZ4_compress_default of the whole buffer (in-process reference)
  Rate lz4_frame_decompress;        // LZ4_decompress_safe of that
  SizeStats payload_bytes;          // per buffer (one eye, one frame): sum of shard payloads
  SizeStats datagram_bytes;         // payload + per-shard datagram header, what goes on the wire
  SizeStats shards;
  SizeStats whole_frame_lz4_bytes;  // LZ4_compress_default of the whole buffer
  SizeStats row_aligned_payload_bytes;  // EncodeOptions::row_aligned = true
  double uniform_pixel_fraction = 0.0;  // pixels covered by uniform chunks
  bool round_trip_ok = true;            // every decoded buffer equals its source
};

// Encodes/decodes every buffer `repeat` times (>= 1).
CodecMeasurement measure_codec(const BufferSet& set, int repeat);

// Mbit/s of `bytes_per_eye_frame` sent for 2 eyes at `hz` frames per second.
inline double stereo_mbit_s(double bytes_per_eye_frame, double hz = 90.0) {
  return bytes_per_eye_frame * 2.0 * hz * 8.0 / 1e6;
}

}  // namespace dhr::bench
