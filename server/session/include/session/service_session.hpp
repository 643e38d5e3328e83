// Internal to the session layer (visibility_service*.cpp): a session's state and a unit of trace work.
#pragma once
#include "net/clock_sync.hpp"
#include "scene/node_overrides.hpp"
#include "session/fov_margin.hpp"
#include "session/pose_predictor.hpp"
#include "session/visibility_service.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "codec/codec_v2.hpp"
#include "secure/envelope.hpp"
#include "secure/replay_window.hpp"

namespace dhr::server {

struct VisibilityService::Session {
  uint64_t token = 0;
  net::PeerAddress peer;
  Hello hello;
  Welcome welcome;
  VisibilityLayout layout;  // where each light sits in the masks (hard, or soft levels when the Welcome grants them)
  // With a key: both handshake randoms, the session's keys and the replay window of the client's datagrams.
  bool secure = false;
  secure::Random client_random{};
  secure::Random server_random{};
  secure::SessionKeys keys;
  secure::ReplayWindow replay;
  int64_t last_receive_ns = 0;
  int64_t last_heartbeat_sent_ns = 0;
  int64_t last_echo_ns = 0;
  bool echoed = false;
  // Poses: the newest received frame number and the pose waiting to be traced.
  bool have_frame = false;
  uint64_t newest_frame_received = 0;
  std::optional<PoseUpdate> pending;
  int64_t pending_receive_ns = 0;
  PosePredictor predictor;        // used with ServiceConfig::predict or adaptive_fov (frame period)
  FovMarginTracker fov_margin;    // used with ServiceConfig::adaptive_fov
  SendRateController rate;        // used with ServiceConfig::rate_control
  bool busy = false;              // a worker is tracing it (claim_work)
  // ServiceConfig::reuse: per eye, the newest trace's record (other sessions' workers read it: replaced only under
  // the service's mutex, and a reader holds its own reference while it traces) and the one the next trace writes
  // (only this session's worker touches it; a new one when a reader still holds the old).
  std::array<std::shared_ptr<ReuseFrame>, 2> reuse_newest;
  std::array<std::shared_ptr<ReuseFrame>, 2> reuse_writing;
  // Pacing (rate control): while the trace rate is capped, the newest frame's datagrams, protected, wait here
  // and pace() sends them at the controller's pacing rate; a newer frame's replace what is left.
  std::mutex pace_mutex;
  std::deque<std::vector<uint8_t>> paced;
  double pace_credit = 1.0;
  int64_t pace_last_ns = 0;
  int64_t last_process_ns = 0;    // the last trace-and-send of both eyes (service clock)
  // The last pose handed to the tracer (identical-pose skip).
  bool have_traced = false;
  std::array<View, 2> traced_views{};
  int64_t traced_scene_time_ns = 0;  // its scene time as sent (in a moving scene, another one is not identical)
  // App-moved nodes: the transforms accepted (scene/node_overrides.hpp), and their revision at the last trace (a
  // changed set is not an identical pose).
  NodeOverrides overrides;
  uint64_t traced_overrides_revision = 0;
  int64_t last_trace_ns = 0;
  uint64_t newest_frame_traced = 0;
  // Codec v2, per eye: the frames traced and sent (the newest kV2ReferenceFrames), the newest frame the client
  // acknowledged holding, and when the eye was last coded intra.
  struct SentFrame {
    uint64_t frame = 0;
    VisibilityBuffer buffer;
    Camera camera;
  };
  struct EyeCodec {
    std::vector<SentFrame> sent;  // ring, kV2ReferenceFrames
    size_t next = 0;
    std::optional<uint64_t> acked;
    int64_t last_intra_ns = 0;
    bool had_intra = false;
  };
  std::array<EyeCodec, 2> codec;
  // The client's newest Heartbeat (echoed back) and the offset estimate from its echoes of ours.
  bool have_peer_heartbeat = false;
  int64_t peer_heartbeat_send_ns = 0;
  int64_t peer_heartbeat_receive_ns = 0;
  net::ClockOffsetEstimator offset;
  // Counters for our Heartbeats. Atomics: the worker sends shards without the service lock.
  // 64 bits so that a session that sent 2^32 datagrams is noticed (the wire carries the low 32 bits; sealed
  // datagrams use them as the nonce and stop there, see send_message).
  std::atomic<uint64_t> next_sequence{0};
  std::atomic<uint64_t> datagrams_sent{0};
  std::atomic<uint64_t> frames_done{0};
  std::atomic<bool> open{true};
  uint64_t datagrams_received = 0;
  uint64_t datagrams_rejected = 0;
  uint64_t frames_dropped = 0;

  SessionInfo info() const { return SessionInfo{token, peer, welcome, newest_frame_traced}; }
};

// One frame to trace: the client's frame number and display time with the views to trace (the pose's own, or
// the predicted ones) and the scene time to trace it at (the pose's, plus the horizon when predicting).
struct VisibilityService::Work {
  std::shared_ptr<Session> session;
  FramePose traced;
  NodeOverrides overrides;  // the session's app transforms when taken (applied at traced.scene_time_ns)
  std::array<std::optional<uint64_t>, 2> acked;  // codec v2: the client's acknowledgements when taken
  bool paced = false;  // the session's rate is capped: its datagrams go through the pacing queue
  int64_t received_ns = 0;  // when the pose arrived (service clock)
};

namespace session_detail {

inline bool same_view(const View& a, const View& b) {
  return a.pose.position == b.pose.position && a.pose.orientation == b.pose.orientation &&
         a.fov.angle_left == b.fov.angle_left && a.fov.angle_right == b.fov.angle_right &&
         a.fov.angle_up == b.fov.angle_up && a.fov.angle_down == b.fov.angle_down;
}

inline double elapsed_ms(int64_t start_ns) { return static_cast<double>(net::steady_now_ns() - start_ns) / 1e6; }

inline uint32_t clamp_u32(uint64_t v) { return v > 0xFFFFFFFFu ? 0xFFFFFFFFu : static_cast<uint32_t>(v); }

inline uint16_t clamp_ms_u16(int64_t ns) {
  const int64_t ms = std::clamp<int64_t>(ns / net::kNsPerMs, 1, 0xFFFF);
  return static_cast<uint16_t>(ms);
}


}  // namespace session_detail
}  // namespace dhr::server
