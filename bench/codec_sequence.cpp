#include "codec_sequence.hpp"

#include "bench_lights.hpp"
#include "bench_timing.hpp"

#include "cli/exit_codes.hpp"
#include "codec/codec.hpp"
#include "codec/codec_v2.hpp"
#include "json_writer.hpp"
#include "protocol/protocol.hpp"
#include "scene/scene.hpp"
#include "session/shipped_defaults.hpp"
#include "traced_buffers.hpp"
#include "traces/eye_model.hpp"
#include "traces/pose_trace.hpp"
#include "trace/reuse/reuse_frame.hpp"
#include "trace/visibility_tracer.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <vector>

namespace dhr::bench {
namespace {

constexpr double kFramePeriodS = 1.0 / 90.0;
constexpr size_t kClientHeldFrames = 32;  // complete frames the client keeps per eye as references

// The writer's indented JSON on one line (the sequence mode's contract: the last stdout line is the object).
std::string one_line(const std::string& json) {
  std::string out;
  bool in_string = false, skipping = false;
  for (size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (in_string) {
      out += c;
      if (c == '\\' && i + 1 < json.size()) out += json[++i];
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '\n') {
      skipping = true;
      continue;
    }
    if (skipping && c == ' ') continue;
    skipping = false;
    if (c == '"') in_string = true;
    out += c;
  }
  return out;
}

// The fastest of `repeats` runs of `run`, in milliseconds.
template <typename F>
double fastest(uint32_t repeats, F&& run) {
  double best = std::numeric_limits<double>::infinity();
  for (uint32_t r = 0; r < std::max(repeats, 1u); ++r) {
    const auto start = std::chrono::steady_clock::now();
    run();
    best = std::min(best, ms_since(start));
  }
  return best;
}

struct EyeState {
  std::map<uint64_t, const VisibilityBuffer*> held;  // complete frames the client holds (newest kClientHeldFrames)
};

}  // namespace

int run_sequence(const SequenceOptions& o) {
  SceneLoadResult loaded = load_scene(o.scene);
  if (!loaded) {
    std::fprintf(stderr, "codec_bench: %s\n", loaded.error.c_str());
    return exit_code::kUsage;
  }
  Scene& scene = *loaded.scene;
  const uint32_t scene_lights = static_cast<uint32_t>(scene.lights.size());
  const double light_range = o.light_range >= 0.0 ? o.light_range : default_bench_light_range(scene, o.lights);
  if (o.lights > scene.lights.size()) add_bench_lights(scene, o.lights, light_range);
  TraceReadResult read = read_pose_trace(o.trace);
  if (!read || read.trace->empty()) {
    std::fprintf(stderr, "codec_bench: %s\n", read ? (o.trace + ": empty trace").c_str() : read.error.c_str());
    return exit_code::kUsage;
  }
  const PoseTrace& trace = *read.trace;
  std::string placement_note;
  const TracePlacement placement = default_trace_placement(o.scene, &placement_note);
  const Pose T_scene_trace = placement_transform(placement, trace.samples.front().head);
  const EyeModel eyes = EyeModel::typical_headset();
  Extent display;
  GuardBand guard;
  split_guard_band(o.size, display, guard);
  const TracedFormat format{display, guard};

  server::TracerOptions tracer_options;
  tracer_options.threads = o.threads;
  tracer_options.soft = o.soft;
  const auto tracer = server::create_tracer(server::TracerBackend::kEmbree, scene, tracer_options);
  const VisibilityLayout layout = o.soft_levels
                                     ? server::layout_for_lights(tracer->light_extents(), tracer->light_count())
                                     : VisibilityLayout::hard(tracer->light_count());
  const uint32_t lights = layout.total_bits();  // bits per mask: what the codecs code

  // Reuse as a session of dhr-server traces: each eye from its own previous trace, the right eye also from the
  // left eye's trace of the frame (VisibilityService; docs/server.md, "Reuse").
  const bool reuse = o.reuse == SequenceOptions::Reuse::kOn ||
                     (o.reuse == SequenceOptions::Reuse::kAuto &&
                      server::shipped::reuse_by_default(tracer->backend() == server::TracerBackend::kEmbree,
                                                        o.soft_levels, scene.has_soft_lights()));
  std::array<server::ReuseFrame, 2> newest, writing;
  uint64_t reused_pixels = 0, rays = 0;

  // Trace every frame first (the codec is timed on its own afterwards).
  std::vector<std::array<VisibilityBuffer, 2>> frames(o.frames);
  std::vector<std::array<Camera, 2>> cameras(o.frames);
  const auto trace_start = std::chrono::steady_clock::now();
  for (uint32_t f = 0; f < o.frames; ++f) {
    const double t = trace.start_time() + o.trace_start_s + f * kFramePeriodS;
    const std::array<View, 2> views = trace_views(trace, trace.sample(t), eyes, T_scene_trace);
    for (size_t e = 0; e < 2; ++e) {
      cameras[f][e] = format.camera(views[e]);
      server::TraceStats stats;
      if (reuse) {
        server::ReuseRequest request;
        request.previous = newest[e].valid() ? &newest[e] : nullptr;
        request.record = &writing[e];
        if (e == 1 && newest[0].valid()) request.shared.push_back(&newest[0]);
        tracer->trace_reusing(cameras[f][e], layout, request, frames[f][e], stats);
        std::swap(newest[e], writing[e]);
      } else {
        tracer->trace_layout(cameras[f][e], layout, frames[f][e], stats);
      }
      reused_pixels += stats.reused_pixels;
      rays += stats.primary_rays + stats.shadow_rays;
    }
    std::fprintf(stderr, "\rcodec_bench: traced %u/%u frames (%.0f s)", f + 1, o.frames, ms_since(trace_start) / 1e3);
  }
  std::fprintf(stderr, "\n");

  const uint32_t ack_delay = static_cast<uint32_t>(std::ceil(o.rtt_ms / (kFramePeriodS * 1e3) - 1e-9));
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::array<EyeState, 2> state;
  double v1_bytes = 0, v2_bytes = 0, v2_payload = 0, shards_v2 = 0, v2_intra_bytes = 0;
  std::vector<double> encode_ms, decode_ms, one_range_encode_ms, one_thread_encode_ms;
  double one_range_bytes = 0;
  // The shipped encode (EncodeOptions' defaults: its ranges on its threads; --encode-ranges and --encode-threads
  // change them) and, on the same frames and references, one range on one thread: the encoder before ranges, for
  // the before/after in one run (alternating which goes first).
  EncodeOptions shipped{};
  if (o.encode_ranges != 0) shipped.v2_ranges = o.encode_ranges;
  if (o.encode_threads != 0) shipped.threads = o.encode_threads;
  const EncodeOptions one_range{.v2_ranges = 1, .threads = 1};
  EncodeOptions one_thread = shipped;  // the shipped ranges on one thread: the same bytes, the threads' gain alone
  one_thread.threads = 1;
  std::vector<EncodedShard> v2_one_range, v2_one_thread;
  bool lossless = true;
  uint64_t pixels = 0, unavailable = 0, inter_frames = 0, fallback_rows = 0, pixels_coded = 0, blocks = 0,
           blocks_copied = 0, blocks_coded = 0;
  std::vector<EncodedShard> v1, v2;
  for (uint32_t f = 0; f < o.frames; ++f) {
    for (int e = 0; e < 2; ++e) {
      const VisibilityBuffer& buffer = frames[f][e];
      CodecStats s1;
      encode_visibility(buffer, EncodeOptions{}, v1, &s1);
      v1_bytes += static_cast<double>(s1.datagram_bytes);

      // The newest frame whose acknowledgement has arrived: complete at the client, ack_delay frames ago.
      // Wire frame numbers are f + 1 (a reference is at least one frame older).
      const uint64_t number = f + 1;
      EyeState& es = state[e];
      V2Reference ref;
      bool have_ref = false;
      for (auto it = es.held.rbegin(); it != es.held.rend(); ++it) {
        if (it->first + ack_delay <= number) {
          ref = V2Reference{it->second, it->first, &cameras[f][e], &cameras[it->first - 1][e]};
          have_ref = true;
          break;
        }
      }
      V2Stats s2, s_one;
      bool encoded = true;
      for (int k = 0; k < 2; ++k) {
        const bool baseline = (k == 0) == ((f + static_cast<uint32_t>(e)) % 2 == 0);
        (baseline ? one_range_encode_ms : encode_ms).push_back(fastest(o.coding_repeats, [&] {
          encoded = encoded && encode_visibility_v2(buffer, number, have_ref ? &ref : nullptr,
                                                    baseline ? one_range : shipped, baseline ? v2_one_range : v2,
                                                    baseline ? &s_one : &s2);
        }));
      }
      one_thread_encode_ms.push_back(fastest(o.coding_repeats, [&] {
        encoded = encoded && encode_visibility_v2(buffer, number, have_ref ? &ref : nullptr, one_thread, v2_one_thread);
      }));
      if (!encoded) {
        std::fprintf(stderr, "codec_bench: v2 encoding failed at frame %u\n", f);
        return 1;
      }
      one_range_bytes += static_cast<double>(s_one.datagram_bytes);
      inter_frames += have_ref ? 1 : 0;
      fallback_rows += s2.v1_fallback_rows;
      pixels_coded += s2.pixels_coded;
      blocks += s2.blocks;
      blocks_copied += s2.blocks_copied;
      blocks_coded += s2.blocks_coded;
      v2_bytes += static_cast<double>(s2.datagram_bytes);
      if (!have_ref) v2_intra_bytes += static_cast<double>(s2.datagram_bytes);
      v2_payload += static_cast<double>(s2.payload_bytes);
      shards_v2 += static_cast<double>(s2.shards);

      // The client: every shard that arrives is decoded against the frame it names and checked.
      std::vector<uint8_t> decoded(buffer.data.size(), 0);
      bool complete = true;
      double dec_ms = 0.0;
      for (const EncodedShard& shard : v2) {
        if (o.loss > 0.0 && unit(rng) < o.loss) {
          complete = false;
          unavailable += shard.pixel_count;
          continue;
        }
        DecodeError err;
        dec_ms += fastest(o.coding_repeats, [&] {
          if (is_v2_payload(shard.payload)) {
            const std::optional<uint64_t> need = v2_reference_frame(shard.payload, number);
            const VisibilityBuffer* rb = nullptr;
            if (need) {
              const auto held = es.held.find(*need);
              rb = held != es.held.end() ? held->second : nullptr;
            }
            err = (need && rb == nullptr) ? DecodeError::kBadPayload
                                          : decode_shard_payload_v2(shard.payload, shard.first_pixel,
                                                                    shard.pixel_count, buffer.width, buffer.height,
                                                                    lights, rb, decoded);
          } else {
            err = decode_shard_payload(shard.payload, shard.first_pixel, shard.pixel_count, buffer.mask_bits, decoded);
          }
        });
        const size_t mb = buffer.bytes_per_mask(), begin = size_t{shard.first_pixel} * mb,
                     end = begin + size_t{shard.pixel_count} * mb;
        if (err != DecodeError::kNone ||
            !std::equal(decoded.begin() + begin, decoded.begin() + end, buffer.data.begin() + begin)) {
          lossless = false;
          complete = false;
          unavailable += shard.pixel_count;
        }
      }
      decode_ms.push_back(dec_ms);
      pixels += buffer.pixel_count();
      if (complete) {
        es.held[number] = &buffer;
        while (es.held.size() > kClientHeldFrames) es.held.erase(es.held.begin());
      }
    }
    std::fprintf(stderr, "\rcodec_bench: coded %u/%u frames", f + 1, o.frames);
  }
  std::fprintf(stderr, "\n");

  const double eye_frames = 2.0 * o.frames;
  const auto mbit = [](double bytes_per_eye_frame) { return bytes_per_eye_frame * 2.0 * 90.0 * 8.0 / 1e6; };
  JsonWriter j;
  j.begin_object();
  j.value("benchmark", "codec_bench").value("mode", "sequence");
  j.value("scene", o.scene).value("trace", o.trace).value("placement", placement_note);
  j.value("tracer", tracer->device_description());
  j.value("frames", o.frames).value("width", o.size.width).value("height", o.size.height);
  j.value("display", std::to_string(display.width) + "x" + std::to_string(display.height));
  j.value("lights", layout.light_count).value("soft_levels", o.soft_levels).value("mask_bits_used", lights);
  j.value("soft_first_samples", o.soft.initial_samples).value("soft_samples", o.soft.max_samples);
  j.value("reuse", reuse);
  j.value("reused_pixels_per_eye_frame", static_cast<double>(reused_pixels) / (2.0 * o.frames), 0);
  j.value("rays_per_eye_frame", static_cast<double>(rays) / (2.0 * o.frames), 0);
  // With more than 32 lights "lights" counts the mask's fields, the slots the scene's lights share.
  j.value("scene_lights", static_cast<unsigned long>(scene.lights.size()));
  j.value("scene_lights_own", static_cast<unsigned long>(scene_lights));
  j.value("added_light_range_m", scene.lights.size() > scene_lights ? light_range : 0.0, 2);
  if (const LightSlots* slots = tracer->light_slots()) {
    j.value("light_slots", static_cast<unsigned long>(slots->slot_count()));
    j.value("lights_per_cell_max", static_cast<unsigned long>(slots->max_lights_per_cell()));
    j.value("lights_without_slot", static_cast<unsigned long>(slots->dropped().size()));
  }
  j.value("rtt_ms", o.rtt_ms, 1).value("ack_delay_frames", ack_delay);
  j.value("loss", o.loss, 4).value("seed", static_cast<unsigned long long>(o.seed));
  j.value("v1_bytes_per_eye_frame", v1_bytes / eye_frames, 1);
  j.value("v2_bytes_per_eye_frame", v2_bytes / eye_frames, 1);
  j.value("v2_payload_bytes_per_eye_frame", v2_payload / eye_frames, 1);
  j.value("v2_shards_per_eye_frame", shards_v2 / eye_frames, 2);
  j.value("v1_mbit_s", mbit(v1_bytes / eye_frames), 3);
  j.value("v2_mbit_s", mbit(v2_bytes / eye_frames), 3);
  j.value("v2_bytes_per_light", layout.light_count > 0 ? v2_bytes / eye_frames / layout.light_count : 0.0, 1);
  j.value("v2_inter_frac", inter_frames / eye_frames, 3);
  // The start-up's intra frames apart from the inter frames that follow (a longer sequence tends to the latter).
  const double intra_frames = eye_frames - static_cast<double>(inter_frames);
  j.value("v2_intra_bytes_per_intra_frame", intra_frames > 0 ? v2_intra_bytes / intra_frames : 0.0, 1);
  j.value("v2_inter_bytes_per_inter_frame", inter_frames > 0 ? (v2_bytes - v2_intra_bytes) / inter_frames : 0.0, 1);
  j.value("v2_v1_fallback_rows", static_cast<unsigned long long>(fallback_rows));
  j.value("v2_pixel_bits_coded_per_eye_frame", static_cast<double>(pixels_coded) / eye_frames, 0);
  j.value("v2_block_lights_copied_frac", blocks > 0 ? static_cast<double>(blocks_copied) / blocks : 0.0, 4);
  j.value("v2_block_lights_coded_frac", blocks > 0 ? static_cast<double>(blocks_coded) / blocks : 0.0, 4);
  j.value("v2_encode_ms_per_eye", median(encode_ms, 0.0), 3);
  j.value("v2_ranges", static_cast<unsigned long>(shipped.v2_ranges));
  j.value("v2_encode_threads", static_cast<unsigned long>(shipped.threads));
  j.value("v2_one_range_mbit_s", mbit(one_range_bytes / eye_frames), 3);
  j.value("v2_one_range_encode_ms_per_eye", median(one_range_encode_ms, 0.0), 3);
  j.value("v2_one_thread_encode_ms_per_eye", median(one_thread_encode_ms, 0.0), 3);
  j.value("v2_decode_ms_per_eye", median(decode_ms, 0.0), 3);
  j.value("coding_repeats", o.coding_repeats);
  j.value("lossless", lossless);
  j.value("unavailable_frac", pixels > 0 ? static_cast<double>(unavailable) / static_cast<double>(pixels) : 0.0, 5);
  j.end_object();
  std::printf("%s\n", one_line(j.str()).c_str());
  return lossless ? 0 : 1;
}

}  // namespace dhr::bench
