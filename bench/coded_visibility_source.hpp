// client_bench's visibility for its frame loops: what a server sends at 90 Hz, without a network. Each pose the
// client's frame loop sends is traced for both eyes (Embree, in the scene's layout: soft levels where lights have
// an extent) and coded with codec v2 against that eye's previous
// frame, as the server codes against an acknowledged one; the frame loop takes it one frame later (p = 1), when
// it is decoded with the client's decoder (decode_shard_payload_v2, shard by shard, against the eye's previous
// decoded frame, as the reassembler does). Tracing and encoding are not the client's work and are not timed;
// decoding is (decode_ms()). A moving scene is traced at each pose's scene time plus `scene_lead_ns`, which the
// frame names: shown one frame later, a lead of one frame period is a server that predicted the display exactly
// (nothing moved since), a lead of 0 one that traced the pose's own time (the warp's motion rule sees one frame
// of motion).
#pragma once
#include "codec/codec.hpp"
#include "frame/visibility_source.hpp"
#include "trace/visibility_tracer.hpp"
#include "visibility/visibility_layout.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace dhr::bench {

class CodedVisibilitySource final : public client::VisibilitySource {
 public:
  // Keeps a reference to the tracer.
  CodedVisibilitySource(server::VisibilityTracer& tracer, const TracedFormat& format, int64_t scene_lead_ns = 0);

  void tick() override {}
  std::optional<client::VisibilityFormat> format() const override;
  bool failed() const override { return false; }
  std::string failure() const override { return {}; }
  void send_pose(const FramePose& pose) override;
  bool take_newest(uint32_t eye, VisibilityFrame& out) override;
  std::optional<int64_t> response_ns(uint64_t /*frame*/) const override { return std::nullopt; }
  client::VisibilitySourceStats stats() const override { return stats_; }

  // Host ms of decoding each eye frame taken so far, and its coded payload bytes.
  const std::vector<double>& decode_ms() const { return decode_ms_; }
  const std::vector<double>& payload_bytes() const { return payload_bytes_; }
  // Host ms spent in send_pose and take_newest so far (tracing, coding, decoding): not the frame loop's own time.
  double busy_ms() const { return busy_ms_; }
  // The calling thread's CPU ms in them (thread_cpu_ms()), for the same subtraction from CPU times.
  double busy_cpu_ms() const { return busy_cpu_ms_; }

 private:
  struct Coded {
    uint64_t frame_number = 0;
    View view;
    int64_t scene_time_ns = 0;
    std::vector<EncodedShard> shards;
  };
  struct EyeState {
    std::optional<Coded> sent;        // coded for the last pose: taken after the next one (p = 1)
    std::optional<Coded> deliverable;
    VisibilityBuffer traced;          // the server's reference: the last buffer traced
    std::optional<uint64_t> traced_frame;
    Camera traced_camera;
    VisibilityBuffer decoded;         // the client's reference: the last frame decoded
  };

  server::VisibilityTracer* tracer_;
  TracedFormat format_;
  uint32_t light_count_;
  VisibilityLayout layout_;  // the scene's, soft levels included: what a client offering them receives
  int64_t scene_lead_ns_ = 0;
  std::array<EyeState, 2> eyes_;
  client::VisibilitySourceStats stats_;
  std::vector<double> decode_ms_;
  std::vector<double> payload_bytes_;
  double busy_ms_ = 0.0;
  double busy_cpu_ms_ = 0.0;
};

// CPU ms the calling thread has used: unlike wall time, not lengthened while other processes of a shared machine
// (or lavapipe's rasterizer threads) hold the cores.
double thread_cpu_ms();

}  // namespace dhr::bench
