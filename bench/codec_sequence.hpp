// codec_bench's sequence mode: N consecutive frames of a recorded head-motion trace (both eyes, 90 Hz),
// traced by the server's Embree tracer, coded with v1 (LZ4 shards) and v2 (context-modelled, against the
// newest frame the client has acknowledged holding) in the same run. Acknowledgements reach the encoder one
// round trip after the frame; with --loss shards are dropped at random (seeded), a frame with a lost shard is
// never acknowledged, and every decoded shard is compared with the traced bits.
#pragma once
#include "math/projection.hpp"
#include "trace/soft/soft_options.hpp"

#include <cstdint>
#include <string>

namespace dhr::bench {

struct SequenceOptions {
  std::string scene;
  std::string trace;
  uint32_t frames = 30;
  Extent size{1984, 1116};  // traced per eye (display + guard band, in the paper's proportion)
  double rtt_ms = 50.0;
  double loss = 0.0;          // probability that a shard is lost
  double trace_start_s = 2.0;
  uint32_t lights = 0;        // 0: the scene's lights; more: point lights added around the scene (many-light runs)
  double light_range = -1.0;  // the added lights' range, m (0: infinite; < 0: default_bench_light_range)
  unsigned threads = 0;       // tracer threads (the codec runs on one)
  uint64_t seed = 1;
  // Soft levels (docs/protocol.md, "Mask layout"): lights with an extent get 3-bit Gray-coded level fields,
  // traced as a soft-capable session's (VisibilityTracer::trace_layout); off: one bit per light.
  bool soft_levels = false;
  server::SoftOptions soft;  // the tracer's sampling of lights with an extent (TracerOptions::soft)
  // Reuse of earlier traces (trace/reuse), as dhr-server's --reuse: auto = what it ships (shipped::reuse_by_default:
  // on with soft levels and a light with an extent), so the coded frames are the ones a session sends.
  enum class Reuse { kAuto, kOn, kOff } reuse = Reuse::kAuto;
  // The shipped encode's v2 row ranges and threads (EncodeOptions' defaults when 0); the one-range and one-thread
  // encodes beside it stay as they are.
  uint32_t encode_ranges = 0;
  uint32_t encode_threads = 0;
  // Each encode and each shard's decode runs this many times on the same inputs and the fastest is timed: other
  // work on a shared machine then shows in fewer of the figures (the bytes are the same every time).
  uint32_t coding_repeats = 1;
};

// Prints progress on stderr and one JSON object as the last stdout line. Returns the exit code (docs/exit-codes.md:
// 2 for a scene or trace that cannot be read).
int run_sequence(const SequenceOptions& options);

}  // namespace dhr::bench
