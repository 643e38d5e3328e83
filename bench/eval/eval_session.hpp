// One setting of the sweep, simulated frame by frame: the client sends each frame's PoseUpdate over a
// simulated uplink; the server side (the Embree tracer, server/PosePredictor for paper+pred, the codec)
// traces each eye and sends VisibilityShard datagrams over a simulated downlink; the client reassembles
// them (shared/core/reassembly) and renders every measured frame with the real EyePipeline, compared with
// the ground truth. Each session has its own VirtualClock and links, so settings do not interact.
#pragma once
#include "core/image_metrics.hpp"
#include "core/protocol.hpp"
#include "core/reassembly.hpp"
#include "eval_render.hpp"
#include "eval_settings.hpp"
#include "net/clock.hpp"
#include "net/simulated_link.hpp"
#include "pose/pose_source.hpp"
#include "pose_predictor.hpp"
#include "visibility_tracer.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace dhr::eval {

// The ground truth of one frame: visibility traced exactly for the displayed views, shaded by the client.
struct Truth {
  std::array<LumaImage, 2> luma;
  std::array<VisibilityBuffer, 2> mask;
};

// Sums over measured frames and eyes (means are taken when the results are written).
struct SettingTotals {
  uint64_t eye_frames = 0;
  uint64_t eye_frames_without_data = 0;  // nothing received yet: every surface pixel unknown
  double bit_error = 0.0;
  std::vector<double> bit_error_per_light;
  double ssim = 0.0;
  double mse = 0.0;
  double unknown_frac = 0.0;
  double client_ms = 0.0;       // GPU timestamps (all three passes) where valid, else host time
  uint64_t client_gpu_timed = 0;
  double frames_behind = 0.0;   // p
  double frames_predicted = 0.0;  // x
  uint64_t traces = 0;          // eyes traced by the server
  double server_ms = 0.0;
  double encode_ms = 0.0;
  double decode_ms = 0.0;       // datagram decode + reassembly, per shard summed
  uint64_t bytes_down = 0;      // visibility datagrams sent
  uint64_t bytes_up = 0;        // pose datagrams sent
  uint64_t poses_sent = 0;
  uint64_t responses = 0;
  double response_ms = 0.0;
  uint64_t predictions = 0;
  uint64_t prediction_fallbacks = 0;
  uint64_t prediction_capped = 0;
  double horizon_ms = 0.0;
  uint64_t datagrams_lost = 0;
};

struct SessionShared {
  server::VisibilityTracer* tracer = nullptr;
  EyeRenderer* renderer = nullptr;
  Extent eye;
  uint32_t light_count = 0;
  const std::vector<client::PoseSample>* history = nullptr;  // every frame so far, index = frame
};

// Views as they arrive after one trip through the wire format (f32 quaternions, renormalized), iterated to a
// fixed point, so what the client displays is exactly what the server can receive and trace.
std::array<View, 2> wire_views(const std::array<View, 2>& views);

class SettingSession {
 public:
  SettingSession(const Setting& setting, const RunOptions& options, const SessionShared& shared);

  // Frame sample.frame: delivers everything due before its display time, sends its PoseUpdate, then
  // delivers everything due at its display time (a zero delay arrives in the same frame).
  void advance(const client::PoseSample& sample);
  // Renders the frame last advanced to with the newest visibility and adds its errors against `truth`.
  void measure(const Truth& truth);

  const Setting& setting() const { return setting_; }
  const SettingTotals& totals() const { return totals_; }

 private:
  void deliver_until(int64_t t_ns, bool inclusive);
  void on_pose(const net::SimulatedDelivery& delivery);
  void on_shard(const net::SimulatedDelivery& delivery);

  Setting setting_;
  SessionShared shared_;
  net::VirtualClock clock_;
  net::SimulatedLink uplink_;
  net::SimulatedLink downlink_;
  VisibilityReassembler reassembler_;
  server::PosePredictor predictor_;
  uint32_t up_sequence_ = 0;
  uint32_t down_sequence_ = 0;
  uint64_t frame_ = 0;
  int64_t now_ns_ = 0;
  std::array<std::optional<uint64_t>, 2> last_used_{};
  VisibilityBuffer scratch_;
  SettingTotals totals_;
};

}  // namespace dhr::eval
