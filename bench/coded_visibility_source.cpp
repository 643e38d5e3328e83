#include "coded_visibility_source.hpp"

#include "bench_timing.hpp"
#include "codec/codec_v2.hpp"

#include <chrono>
#include <ctime>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

namespace dhr::bench {

double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

CodedVisibilitySource::CodedVisibilitySource(server::VisibilityTracer& tracer, const TracedFormat& format,
                                             int64_t scene_lead_ns)
    : tracer_(&tracer),
      format_(format),
      light_count_(tracer.light_count()),
      layout_(server::layout_for_lights(tracer.light_extents(), tracer.light_count())),
      scene_lead_ns_(scene_lead_ns) {}

std::optional<client::VisibilityFormat> CodedVisibilitySource::format() const {
  return client::VisibilityFormat{format_, light_count_, 0};
}

void CodedVisibilitySource::send_pose(const FramePose& pose) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_ms();
  const int64_t scene_time_ns = pose.scene_time_ns + scene_lead_ns_;
  if (tracer_->moves()) tracer_->set_scene_time(static_cast<double>(scene_time_ns) * 1e-9);
  for (uint32_t e = 0; e < 2; ++e) {
    EyeState& eye = eyes_[e];
    eye.deliverable = std::move(eye.sent);
    eye.sent.reset();
    const Camera camera = format_.camera(pose.views[e]);
    VisibilityBuffer buffer;
    server::TraceStats trace_stats;
    tracer_->trace_layout(camera, layout_, buffer, trace_stats);  // as a session granted soft levels traces
    V2Reference reference;
    reference.buffer = &eye.traced;
    reference.current_camera = &camera;
    reference.reference_camera = &eye.traced_camera;
    const bool inter = eye.traced_frame && *eye.traced_frame < pose.frame;
    if (inter) reference.frame_number = *eye.traced_frame;
    Coded coded;
    coded.frame_number = pose.frame;
    coded.view = pose.views[e];
    coded.scene_time_ns = scene_time_ns;
    if (!encode_visibility_v2(buffer, pose.frame, inter ? &reference : nullptr, EncodeOptions{}, coded.shards)) {
      throw std::runtime_error("codec v2 could not code frame " + std::to_string(pose.frame));
    }
    eye.sent = std::move(coded);
    eye.traced = std::move(buffer);
    eye.traced_frame = pose.frame;
    eye.traced_camera = camera;
  }
  busy_ms_ += ms_since(start);
  busy_cpu_ms_ += thread_cpu_ms() - cpu_start;
}

bool CodedVisibilitySource::take_newest(uint32_t e, VisibilityFrame& out) {
  EyeState& eye = eyes_[e];
  if (!eye.deliverable) return false;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_ms();
  const Coded coded = std::move(*eye.deliverable);
  eye.deliverable.reset();
  const Extent size = format_.buffer();
  // Allocated before the clock starts: the client's reassembler holds its frames' storage across frames.
  VisibilityFrame frame;
  frame.buffer = VisibilityBuffer::create(size.width, size.height, layout_.total_bits());
  const bool has_reference = eye.decoded.width == size.width && eye.decoded.height == size.height;
  size_t bytes = 0;
  const auto decode_start = std::chrono::steady_clock::now();
  for (const EncodedShard& shard : coded.shards) {
    const std::span<const uint8_t> payload(shard.payload);
    const DecodeError error = decode_shard_payload_v2(payload, shard.first_pixel, shard.pixel_count, size.width,
                                                      size.height, layout_.total_bits(),
                                                      has_reference ? &eye.decoded : nullptr,
                                                      std::span<uint8_t>(frame.buffer.data));
    if (error != DecodeError::kNone) {
      throw std::runtime_error("codec v2 could not decode frame " + std::to_string(coded.frame_number));
    }
    bytes += shard.payload.size();
  }
  decode_ms_.push_back(ms_since(decode_start));
  payload_bytes_.push_back(static_cast<double>(bytes));
  frame.frame_number = coded.frame_number;
  frame.eye = e == 0 ? Eye::kLeft : Eye::kRight;
  frame.view = coded.view;
  frame.scene_time_ns = coded.scene_time_ns;
  frame.row_valid.assign(size.height, 1);
  frame.rows_valid = size.height;
  frame.complete = true;
  eye.decoded = frame.buffer;  // the next frame's reference
  out = std::move(frame);
  stats_.frames_received += 1;
  stats_.bytes_received += bytes;
  busy_ms_ += ms_since(start);
  busy_cpu_ms_ += thread_cpu_ms() - cpu_start;
  return true;
}

}  // namespace dhr::bench
