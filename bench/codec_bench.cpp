// codec_bench: the visibility codec on realistic buffers, printed as JSON (never asserts).
//   codec_bench [--scene PATH|synthetic] [--size WxH] [--repeat N] [--out FILE] [--lz4-seconds N] [--threads N]
//   codec_bench --scene PATH --trace FILE --frames N --size WxH [--rtt-ms R] [--loss P] [--lights N]
//               [--light-range M] [--trace-start S] [--seed N] [--threads N] [--soft-levels on|off] [--encode-ranges N]
//               [--encode-threads N] [--soft-samples FIRST,ALL] [--reuse auto|on|off] [--coding-repeats N]
//                                                               sequence mode, v1 against v2 (codec_sequence.hpp)
// Buffer sets: "traced" (the scene traced by the server's Embree tracer from each camera bookmark, both
// eyes; only when built with dhr_server) and always "synthetic" (make_room_visibility, same size and
// light count). Per set: encode/decode MB/s of raw mask bytes (one thread), compressed bytes per eye
// frame (sharded scheme vs whole-frame LZ4), shard count, Mbit/s at 90 Hz stereo, and `lz4 -b1` on the
// same bytes as the reference. docs/performance.md ("Codec") has measured numbers.
#include "cli/exit_codes.hpp"
#include "scene/light_slots.hpp"
#include "cli/help_flag.hpp"
#include "codec_measure.hpp"
#include "protocol/protocol.hpp"
#include "metrics/visibility_synthetic.hpp"
#include "json_writer.hpp"
#include "lz4_reference.hpp"

#include <lz4.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "codec_sequence.hpp"  // SequenceOptions; run_sequence needs the tracer
#if defined(DHR_BENCH_HAVE_TRACER)
#include "traced_buffers.hpp"
#endif

namespace {

using namespace dhr;
using namespace dhr::bench;

struct Options {
  std::string scene;  // empty: the default; "synthetic": no tracing
  uint32_t width = 1984;
  uint32_t height = 1116;
  int repeat = 5;
  int lz4_seconds = 1;
  unsigned threads = 0;
  std::string out;
  SequenceOptions sequence;  // used when --trace is given
  std::vector<std::string> sequence_only;  // options given that only the sequence mode reads
};

// Options of the sequence mode alone: given without --trace they are named in a warning.
bool sequence_only(const std::string& a) {
  for (const char* s : {"--frames", "--rtt-ms", "--loss", "--trace-start", "--lights", "--light-range",
                        "--soft-levels", "--encode-ranges", "--encode-threads", "--soft-samples", "--reuse",
                        "--coding-repeats", "--seed"})
    if (a == s) return true;
  return false;
}

constexpr uint32_t kDefaultLights = 3;
constexpr int kSyntheticBuffers = 4;

std::string default_scene() {
  const std::string data = std::string(DHR_SHARED_DATA_DIR) + "/scenes/living_room.glb";
  if (std::filesystem::exists(data)) return data;
  return std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room.gltf";
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "unknown";
}

int usage(const char* argv0, FILE* to = stderr) {
  std::fprintf(to,
               "usage: %s [--scene PATH|synthetic] [--size WxH] [--repeat N] [--out FILE] [--lz4-seconds N] "
               "[--threads N]\n"
               "       %s --scene PATH --trace FILE --frames N --size WxH [--rtt-ms R] [--loss P] [--lights N] "
               "[--light-range M] [--trace-start S] [--seed N] [--threads N] [--soft-levels on|off] [--encode-ranges N] "
               "[--encode-threads N] [--soft-samples FIRST,ALL] [--reuse auto|on|off] [--coding-repeats N]\n",
               argv0, argv0);
  return to == stderr ? exit_code::kUsage : exit_code::kOk;
}

bool parse_option(const std::string& a, const char* v, Options& o);

// False after naming on stderr the option that is unknown, lacks its value or has a value out of its range.
bool parse_args(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr, "codec_bench: %s: unknown, or its value is missing\n", a.c_str());
      return false;
    }
    const char* v = argv[++i];
    if (sequence_only(a)) o.sequence_only.push_back(a);
    if (!parse_option(a, v, o)) {
      std::fprintf(stderr, "codec_bench: %s %s: unknown option or value out of range\n", a.c_str(), v);
      return false;
    }
  }
  return true;
}

bool parse_option(const std::string& a, const char* v, Options& o) {
  if (a == "--scene") {
    o.scene = v;
  } else if (a == "--size") {
    unsigned w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(v, "%ux%u%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > kMaxBufferDimension ||
        h > kMaxBufferDimension)
      return false;
    o.width = w;
    o.height = h;
  } else if (a == "--repeat") {
    o.repeat = std::atoi(v);
    if (o.repeat < 1) return false;
  } else if (a == "--lz4-seconds") {
    o.lz4_seconds = std::atoi(v);
    if (o.lz4_seconds < 1) return false;
  } else if (a == "--threads") {
    o.threads = static_cast<unsigned>(std::atoi(v));
  } else if (a == "--out") {
    o.out = v;
  } else if (a == "--trace") {
    o.sequence.trace = v;
  } else if (a == "--frames") {
    const int n = std::atoi(v);
    if (n < 1 || n > 100000) return false;
    o.sequence.frames = static_cast<uint32_t>(n);
  } else if (a == "--rtt-ms" || a == "--loss" || a == "--trace-start") {
    char* end = nullptr;
    const double x = std::strtod(v, &end);
    if (end == v || *end != '\0' || !std::isfinite(x) || x < 0.0) return false;
    if (a == "--loss" && x > 1.0) return false;
    (a == "--rtt-ms" ? o.sequence.rtt_ms : a == "--loss" ? o.sequence.loss : o.sequence.trace_start_s) = x;
  } else if (a == "--lights") {
    const int n = std::atoi(v);
    if (n < 1 || n > static_cast<int>(kMaxSlotLights)) return false;
    o.sequence.lights = static_cast<uint32_t>(n);
  } else if (a == "--light-range") {
    char* end = nullptr;
    const double x = std::strtod(v, &end);
    if (end == v || *end != '\0' || !std::isfinite(x) || x < 0.0 || x > 1000.0) return false;
    o.sequence.light_range = x;
  } else if (a == "--soft-levels") {
    if (std::string(v) != "on" && std::string(v) != "off") return false;
    o.sequence.soft_levels = std::string(v) == "on";
  } else if (a == "--encode-ranges" || a == "--encode-threads") {
    const int n = std::atoi(v);
    if (n < 1 || n > 64) return false;
    (a == "--encode-ranges" ? o.sequence.encode_ranges : o.sequence.encode_threads) = static_cast<uint32_t>(n);
  } else if (a == "--coding-repeats") {  // the fastest of N runs of each encode and decode is timed
    const int n = std::atoi(v);
    if (n < 1 || n > 100) return false;
    o.sequence.coding_repeats = static_cast<uint32_t>(n);
  } else if (a == "--soft-samples") {  // the server's adaptive rule (SoftOptions): FIRST samples, ALL where they disagree
    unsigned first = 0, all = 0;
    char tail = 0;
    if (std::sscanf(v, "%u,%u%c", &first, &all, &tail) != 2) return false;
    o.sequence.soft = server::SoftOptions{first, all};
    if (server::validate_soft_options(o.sequence.soft)) return false;
  } else if (a == "--reuse") {  // as dhr-server's: auto = what it ships (soft levels and a light with an extent)
    const std::string r = v;
    if (r != "auto" && r != "on" && r != "off") return false;
    using R = SequenceOptions::Reuse;
    o.sequence.reuse = r == "on" ? R::kOn : r == "off" ? R::kOff : R::kAuto;
  } else if (a == "--seed") {
    o.sequence.seed = std::strtoull(v, nullptr, 10);
  } else {
    return false;
  }
  return true;
}

void write_sizes(JsonWriter& j, const char* key, const SizeStats& s) {
  j.begin_object(key).value("mean", s.mean, 1).value("min", s.min).value("max", s.max).end_object();
}

void write_rate(JsonWriter& j, const char* key, const Rate& r) {
  j.begin_object(key).value("median", r.median_mb_s, 1).value("best", r.best_mb_s, 1).end_object();
}

void write_set(JsonWriter& j, const BufferSet& set, int repeat, int lz4_seconds) {
  const CodecMeasurement m = measure_codec(set, repeat);
  const VisibilityBuffer& first = set.buffers.front();
  j.begin_object();
  j.value("name", set.name).value("source", set.source);
  if (!set.tracer.empty()) j.value("tracer", set.tracer).value("trace_ms_per_eye_mean", set.trace_ms_mean, 1);
  j.value("light_count", first.light_count).value("mask_bits", static_cast<unsigned>(first.mask_bits));
  j.value("width", first.width).value("height", first.height).value("buffers", m.buffers);
  j.begin_array("labels");
  for (const std::string& l : set.labels) j.value(nullptr, l);
  j.end_array();
  j.value("raw_bytes_per_frame", m.raw_bytes_per_buffer);
  write_rate(j, "encode_mb_s", m.encode);
  write_rate(j, "decode_mb_s", m.decode);
  j.begin_object("sharded");
  write_sizes(j, "payload_bytes_per_frame", m.payload_bytes);
  write_sizes(j, "datagram_bytes_per_frame", m.datagram_bytes);
  write_sizes(j, "shards_per_frame", m.shards);
  write_sizes(j, "row_aligned_payload_bytes_per_frame", m.row_aligned_payload_bytes);
  j.value("uniform_pixel_fraction", m.uniform_pixel_fraction, 4);
  j.value("compression_ratio", static_cast<double>(m.raw_bytes_per_buffer) / m.payload_bytes.mean, 2);
  j.value("mbit_s_90hz_stereo", stereo_mbit_s(m.datagram_bytes.mean), 3);
  j.value("payload_mbit_s_90hz_stereo", stereo_mbit_s(m.payload_bytes.mean), 3);
  j.end_object();
  j.begin_object("whole_frame_lz4");
  write_sizes(j, "bytes_per_frame", m.whole_frame_lz4_bytes);
  write_rate(j, "compress_mb_s", m.lz4_frame_compress);
  write_rate(j, "decompress_mb_s", m.lz4_frame_decompress);
  j.value("mbit_s_90hz_stereo", stereo_mbit_s(m.whole_frame_lz4_bytes.mean), 3);
  j.end_object();
  j.value("sharded_payload_overhead_vs_whole_frame",
          m.whole_frame_lz4_bytes.mean > 0 ? m.payload_bytes.mean / m.whole_frame_lz4_bytes.mean - 1.0 : 0.0, 4);
  j.value("round_trip_ok", m.round_trip_ok);

  std::vector<const std::vector<uint8_t>*> raw;
  for (const VisibilityBuffer& b : set.buffers) raw.push_back(&b.data);
  const Lz4CliResult cli = run_lz4_cli(raw, lz4_seconds);
  j.begin_object("lz4_cli");
  j.value("available", cli.available).value("command", cli.command);
  if (!cli.available) {
    j.value("error", cli.error);
  } else {
    double c = 0.0, d = 0.0, bytes = 0.0;
    for (const Lz4CliRun& r : cli.runs) {
      c += r.compress_mb_s;
      d += r.decompress_mb_s;
      bytes += static_cast<double>(r.compressed_bytes);
    }
    const double n = static_cast<double>(cli.runs.size());
    j.value("version", cli.version);
    j.value("compress_mb_s_mean", c / n, 1).value("decompress_mb_s_mean", d / n, 1);
    j.value("compressed_bytes_per_frame_mean", bytes / n, 1);
    j.begin_array("runs");
    for (const Lz4CliRun& r : cli.runs)
      j.begin_object()
          .value("input_bytes", r.input_bytes)
          .value("compressed_bytes", r.compressed_bytes)
          .value("compress_mb_s", r.compress_mb_s, 1)
          .value("decompress_mb_s", r.decompress_mb_s, 1)
          .end_object();
    j.end_array();
  }
  j.end_object();
  j.end_object();
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (cli::asks_for_help(argc, argv)) return usage(argv[0], stdout);
  if (!parse_args(argc, argv, o)) return usage(argv[0]);
  if (o.scene.empty()) o.scene = default_scene();
  if (!o.sequence.trace.empty()) {
#if defined(DHR_BENCH_HAVE_TRACER)
    o.sequence.scene = o.scene;
    o.sequence.size = Extent{o.width, o.height};
    o.sequence.threads = o.threads;
    return run_sequence(o.sequence);
#else
    std::fprintf(stderr, "codec_bench: sequence mode needs the tracer (built with DHR_BUILD_SERVER=OFF)\n");
    return 1;
#endif
  }

  if (!o.sequence_only.empty()) {
    std::string names;
    for (const std::string& n : o.sequence_only) names += (names.empty() ? "" : ", ") + n;
    std::fprintf(stderr, "codec_bench: warning: %s: only the sequence mode (--trace) reads them; ignored\n",
                 names.c_str());
  }
  std::vector<BufferSet> sets;
  std::vector<std::string> notes;
  uint32_t lights = kDefaultLights;
  if (o.scene != "synthetic") {
#if defined(DHR_BENCH_HAVE_TRACER)
    BufferSet traced;
    std::string error;
    if (trace_bookmark_buffers(o.scene, Extent{o.width, o.height}, o.threads, traced, &error)) {
      lights = traced.buffers.front().light_count;
      sets.push_back(std::move(traced));
    } else {
      // A scene the user named that cannot be traced is an error, not a footnote to synthetic results.
      std::fprintf(stderr, "codec_bench: --scene %s: %s\n", o.scene.c_str(), error.c_str());
      return exit_code::kUsage;
    }
#else
    notes.push_back("no traced buffers: built without dhr_server (DHR_BUILD_SERVER=OFF)");
#endif
  }
  BufferSet synthetic;
  synthetic.name = "synthetic";
  synthetic.source = "make_room_visibility(" + std::to_string(o.width) + ", " + std::to_string(o.height) + ", " +
                     std::to_string(lights) + ", seed 1.." + std::to_string(kSyntheticBuffers) + ")";
  for (int s = 1; s <= kSyntheticBuffers; ++s) {
    synthetic.labels.push_back("seed " + std::to_string(s));
    synthetic.buffers.push_back(make_room_visibility(o.width, o.height, lights, static_cast<uint64_t>(s)));
  }
  sets.push_back(std::move(synthetic));

  JsonWriter j;
  j.begin_object();
  j.value("benchmark", "codec_bench");
  j.begin_object("device");
  j.value("cpu", cpu_model()).value("hardware_threads", std::thread::hardware_concurrency());
  j.value("build_type", DHR_BUILD_TYPE).value("compiler", __VERSION__).value("lz4_library", LZ4_versionString());
  j.end_object();
  j.begin_object("settings");
  j.value("scene", o.scene).value("width", o.width).value("height", o.height).value("repeat", o.repeat);
  j.value("fov_deg_horizontal", 90.0, 1).value("stereo_hz", 90.0, 1).value("codec_threads", 1);
  j.value("max_shard_payload", static_cast<unsigned long>(EncodeOptions{}.max_payload));
  j.value("uniform_min_bytes", static_cast<unsigned long>(EncodeOptions{}.uniform_min_bytes));
  j.value("datagram_header_bytes_per_shard", static_cast<unsigned long>(kShardFixedSize));
  j.end_object();
  j.begin_array("sets");
  for (const BufferSet& set : sets) write_set(j, set, o.repeat, o.lz4_seconds);
  j.end_array();
  j.begin_array("notes");
  for (const std::string& n : notes) j.value(nullptr, n);
  j.end_array();
  j.end_object();

  const std::string text = j.str() + "\n";
  std::fputs(text.c_str(), stdout);
  if (!o.out.empty()) {
    std::ofstream out(o.out);
    out << text;
    if (!out) {
      std::fprintf(stderr, "codec_bench: cannot write %s\n", o.out.c_str());
      return 1;
    }
  }
  return 0;
}
