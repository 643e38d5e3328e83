// One setting of the sweep, simulated frame by frame with the real session layers: a client::VisibilityClient
// (handshake, heartbeats, poses, reassembly, publication) and a server::VisibilityService (sessions,
// prediction for paper+pred, tracing, encoding) talk over two net::SimulatedLinks on the setting's own
// net::VirtualClock, so settings do not interact and every run is deterministic. The client renders every
// measured frame with the client's own frame loop (a client::FrameCoordinator with one GPU slot over the run's
// shared StereoPipeline: the newest visibility, the FramePlanner, both eyes' passes), against the ground truth.
//
// Server compute time is modelled, not measured: each traced eye takes RunOptions::server_ms / 2 of virtual
// time (the service's clock runs on while it traces), so results never depend on the host's speed. The
// host's trace, encode and decode times are recorded as run-time metrics only.
#pragma once
#include "metrics/image_metrics.hpp"
#include "eval_render.hpp"
#include "eval_settings.hpp"
#include "eval_truth.hpp"
#include "net/clock.hpp"
#include "net/simulated_link.hpp"
#include "frame/frame_coordinator.hpp"
#include "frame/network_visibility_source.hpp"
#include "link/visibility_client.hpp"
#include "plan/frame_planner.hpp"
#include "pose/pose_source.hpp"
#include "session/visibility_service.hpp"
#include "trace/visibility_tracer.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace dhr::eval {


// Sums over measured frames and eyes (means are taken when the results are written).
struct SettingTotals {
  uint64_t eye_frames = 0;
  uint64_t eye_frames_without_data = 0;  // nothing received yet: every surface pixel unknown
  double bit_error = 0.0;
  std::vector<double> bit_error_per_light;
  // visibility_error.hpp: |k shown - k exact| summed over surface pixels, per light; the surface pixels.
  std::vector<double> visibility_error_per_light;
  uint64_t surface_pixels = 0;
  uint64_t display_pixels = 0;  // of every measured eye-frame
  double ssim = 0.0;
  double mse = 0.0;
  double flip = 0.0;
  uint64_t flip_frames = 0;     // eye-frames with a FLIP value
  double unknown_frac = 0.0;     // surface pixels without a mask from their own eye's buffer (filled or not)
  double filled_other_eye = 0.0;  // shares of the display pixels, summed over eye-frames
  double filled_shadow_map = 0.0;
  double filled_older = 0.0;      // this eye's previous buffer
  double filled_neighbour = 0.0;  // the nearest old pixel on the pixel's tangent plane
  double edges_shadow_map = 0.0;  // known pixels whose undecided bits took the shadow maps
  double shadow_overrides = 0.0;  // known pixels where a confident shadow-map bit replaced an agreed one
  double motion_unknown = 0.0;    // pixels with bits motion made unknown (the warp's motion rule)
  double unfilled = 0.0;          // shaded lit
  double disoccluded = 0.0;       // the depth test's share (part of unknown_frac)
  double traced_depth_ms = 0.0;   // GPU time of the traced cameras' depth (full's depth test)
  double warp_ms = 0.0;           // GPU time of the warp pass
  double client_ms = 0.0;       // GPU timestamps (all three passes) where valid, else host time
  uint64_t client_gpu_timed = 0;
  uint64_t client_forward = 0;  // eye frames rendered on the forward pass
  double frames_behind = 0.0;   // p
  double frames_predicted = 0.0;  // x
  uint64_t responses = 0;
  double response_ms = 0.0;
  // From the session layers, over the whole run (warm-up included).
  uint64_t traces = 0;          // eyes traced by the service
  server::TraceStats trace_stats;  // their rays, summed (ModelledTimeTracer)
  double server_ms = 0.0;       // host wall time of the tracer
  double encode_ms = 0.0;       // host wall time: restricting lights, codec, datagram encoding and send
  double decode_ms = 0.0;       // host wall time of the client's on_datagram (decode + reassembly)
  uint64_t bytes_down = 0;      // VisibilityShard datagram bytes sent
  uint64_t predictions = 0;
  uint64_t prediction_fallbacks = 0;
  uint64_t prediction_capped = 0;
  double horizon_ms = 0.0;
  uint64_t eyes_fov_widened = 0;  // traced eyes whose FOV the service widened (adaptive FOV)
  double fov_span_ratio = 0.0;    // sum over traced eyes of traced / display tangent area
  uint64_t poses_skipped_identical = 0;
  uint64_t poses_superseded = 0;
  uint64_t datagrams_lost = 0;
  double connect_ms = 0.0;      // virtual time from the first Hello to the end of the connection phase
};

struct SessionShared {
  server::VisibilityTracer* tracer = nullptr;
  EyeRenderer* renderer = nullptr;
  // A setting whose client reads its own previous display frame (WarpSettings::depth_splat) gets its own renderer,
  // made with these: on the shared one that frame would be another setting's.
  const Scene* scene = nullptr;
  render::ShadowMapSettings shadow_maps;
  bool forward = false;
  Extent eye;
  uint32_t light_count = 0;
  uint32_t soft_lights = 0;  // bit i: light i has an extent (the client offers soft levels for them)
  const std::vector<FramePose>* history = nullptr;  // every frame so far, index = frame
  size_t frames_total = 0;                          // frames the run plays (the planner's history holds them all)
  uint32_t light_slots = 0;  // the fields of a scene whose lights share light slots (offered in the Hello); 0: none
};

// Views as they arrive after one trip through the wire format (f32 quaternions, renormalized), iterated to a
// fixed point, so what the client displays is exactly what the server can receive and trace.
std::array<View, 2> wire_views(const std::array<View, 2>& views);

// The service's clock: the setting's virtual clock plus the modelled compute time of the trace in progress.
class ServerClock final : public net::Clock {
 public:
  explicit ServerClock(const net::VirtualClock& base) : base_(base) {}
  int64_t now_ns() const override { return base_.now_ns() + busy_ns_; }
  void add_busy_ns(int64_t ns) { busy_ns_ += ns; }
  int64_t take_busy_ns();  // returns the time spent and resets it (the trace is over)

 private:
  const net::VirtualClock& base_;
  int64_t busy_ns_ = 0;
};

// The shared tracer as one setting's service sees it: each trace moves that setting's ServerClock on by the
// modelled time per eye.
class ModelledTimeTracer final : public server::VisibilityTracer {
 public:
  ModelledTimeTracer(server::VisibilityTracer& inner, ServerClock& clock, int64_t ns_per_eye)
      : inner_(inner), clock_(clock), ns_per_eye_(ns_per_eye) {}
  server::TracerBackend backend() const override { return inner_.backend(); }
  std::string device_description() const override { return inner_.device_description(); }
  const server::AccelStats& accel_stats() const override { return inner_.accel_stats(); }
  uint32_t light_count() const override { return inner_.light_count(); }
  std::vector<bool> light_extents() const override { return inner_.light_extents(); }
  const LightSlots* light_slots() const override { return inner_.light_slots(); }
  // Motion is the inner tracer's (shared with the truth, which moves it to each display's scene time: the service
  // moves it back to its frame's before every trace).
  const SceneAnimation* scene_animation() const override { return inner_.scene_animation(); }
  void set_scene_time(double t, const NodeOverrides* overrides = nullptr) override {
    inner_.set_scene_time(t, overrides);
  }
  bool moves() const override { return inner_.moves(); }
  double last_motion_update_ms() const override { return inner_.last_motion_update_ms(); }
  void trace(const Camera& camera, VisibilityBuffer& out, server::TraceStats& out_stats) override;
  // The inner tracer's own subsets and layouts (soft levels sampled as it samples them), each one eye's time.
  void trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out, server::TraceStats& out_stats) override;
  void trace_layout(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out,
                    server::TraceStats& out_stats) override;
  // The inner tracer's reuse (the default method on a scene with soft lights, as dhr-server --reuse auto).
  void trace_reusing(const Camera& camera, const VisibilityLayout& layout, const server::ReuseRequest& request,
                     VisibilityBuffer& out, server::TraceStats& out_stats) override;
  // The rays and pixels of every trace so far, summed (the times are the host's, not summed).
  const server::TraceStats& sums() const { return sums_; }

 private:
  void traced(const server::TraceStats& stats);
  server::VisibilityTracer& inner_;
  ServerClock& clock_;
  int64_t ns_per_eye_;
  server::TraceStats sums_;
};

// The service's DatagramSender: forwards to the downlink and counts the visibility bytes.
class CountingSender final : public net::DatagramSender {
 public:
  explicit CountingSender(net::SimulatedLink& link) : link_(link) {}
  bool send_to(std::span<const uint8_t> datagram, const net::PeerAddress& to) override;
  uint64_t shard_bytes() const { return shard_bytes_; }

 private:
  net::SimulatedLink& link_;
  uint64_t shard_bytes_ = 0;
};

// The setting's VisibilityClient as the client's frame loop sees it. SettingSession::advance drives the client
// itself (ticks, poses) on the setting's virtual clock, in event order, before the frame is rendered, so the frame
// loop's tick and send_pose are no-ops here. `local` takes no server visibility (the client's shadow maps only).
class SessionVisibilitySource final : public client::VisibilitySource {
 public:
  SessionVisibilitySource(client::VisibilityClient& client, bool server_visibility)
      : network_(client), server_visibility_(server_visibility) {}
  void tick() override {}
  std::optional<client::VisibilityFormat> format() const override { return network_.format(); }
  bool failed() const override { return network_.failed(); }
  std::string failure() const override { return network_.failure(); }
  void send_pose(const FramePose& /*pose*/) override {}
  bool take_newest(uint32_t eye, VisibilityFrame& out) override {
    return server_visibility_ && network_.take_newest(eye, out);
  }
  std::optional<int64_t> response_ns(uint64_t frame) const override { return network_.response_ns(frame); }
  client::VisibilitySourceStats stats() const override { return network_.stats(); }

 private:
  client::NetworkVisibilitySource network_;
  bool server_visibility_;
};

class SettingSession {
 public:
  // Runs the connection phase (handshake and a heartbeat round trip, see connect()); throws
  // std::runtime_error when the client cannot connect. index: the setting's place in the run; in a moving scene
  // its frames re-render their own shadow maps on the shared pipeline (owner index + 1; the truth's are owner 0's),
  // as one client's would: which faces, and when, depends on what its frames show.
  SettingSession(const Setting& setting, const RunOptions& options, const SessionShared& shared, uint32_t index);
  ~SettingSession();

  // Frame sample.frame: delivers everything due before its display time, ticks both sides, sends its
  // PoseUpdate, then delivers everything due at its display time (a zero delay arrives in the same frame).
  void advance(const FramePose& sample);
  // Renders the frame last advanced to with the newest visibility and adds its errors against `truth`.
  void measure(const Truth& truth);

  const Setting& setting() const { return setting_; }
  // Writes the shaded eyes, the exact ones and the wrong bits of trace frame `frame` to <out>/snapshots.
  void snapshot_at(uint64_t frame) { snapshot_frame_ = frame; }
  // The totals, with the session layers' counters folded in.
  SettingTotals totals() const;

 private:
  void connect();
  void run_until(int64_t t_ns, bool inclusive);
  void process_on_server(int64_t t_ns);
  void deliver_to_client(const net::SimulatedDelivery& delivery);
  void add_image_errors(const EyeRender& rendered, const Truth& truth, int eye);
  void write_snapshot(const EyeRender& rendered, const Truth& truth, int eye) const;
  int64_t display_ns(const FramePose& sample) const { return time_offset_ns_ + sample.display_time_ns; }
  double pixels_per_eye() const { return static_cast<double>(shared_.eye.width) * shared_.eye.height; }

  Setting setting_;
  SessionShared shared_;
  double cap_ms_ = 0.0;  // the predictor's horizon cap (paper+pred)
  render::WarpSettings warp_;
  std::optional<uint64_t> snapshot_frame_;  // RunOptions::snapshot_frame, as a trace frame index
  std::string snapshot_dir_;  // the client's warp for the setting's method
  TracedFormat format_;  // the eye size and guard band, as the Welcome must grant them
  net::VirtualClock clock_;
  ServerClock server_clock_;
  net::SimulatedLink uplink_;    // client -> server, stamped with the client's clock
  net::SimulatedLink downlink_;  // server -> client, stamped with the service's clock
  CountingSender server_out_;
  ModelledTimeTracer tracer_;
  std::unique_ptr<server::VisibilityService> service_;
  std::unique_ptr<client::VisibilityClient> client_;
  std::unique_ptr<SessionVisibilitySource> source_;
  std::unique_ptr<EyeRenderer> own_renderer_;  // WarpSettings::depth_splat (SessionShared::scene)
  EyeRenderer* renderer_ = nullptr;             // own_renderer_ or the shared one
  std::unique_ptr<client::FrameCoordinator> frames_;  // the client's frame loop (its planner: the frame policy)
  client::FrameSink sink_;                            // nothing: measure() reads the eyes back itself
  client::FrameRecord last_record_;                   // of the frame measure() rendered last
  bool server_work_ = false;     // a datagram reached the service since it last processed
  int64_t server_free_ns_ = 0;   // the service's worker is busy tracing until then
  int64_t time_offset_ns_ = 0;   // virtual time of trace frame 0 (after the connection phase)
  uint64_t frame_ = 0;
  SettingTotals totals_;
};

}  // namespace dhr::eval
