// VisibilityService: the server's session layer, transport-agnostic (docs/protocol.md "Handshake and
// session", docs/server.md "Serving clients"; NodeTransform: docs/motion.md "App-moved nodes"). Datagrams come in through on_datagram() with their sender's
// address; replies and visibility shards go out through a net::DatagramSender (a ServerEndpoint, an
// ImpairedSender, or a SimulatedLink in tests and dhr-eval); time comes from a net::Clock (VirtualClock in
// tests), so the whole service runs deterministically without sockets or threads.
//
// Threads: on_datagram() on the socket thread, process_pending() on one worker thread (it traces), tick()
// on either. One mutex guards the session table; it is held briefly and never while tracing or encoding.
// A moving scene (VisibilityTracer::moves()) is traced at each frame's scene time: another mutex is held from
// the tracer's set_scene_time through both eyes' traces, so parallel workers take turns on the tracer.
// Memory is bounded whatever arrives: at most max_sessions sessions, one pending pose each, no queues.
#pragma once
#include "codec/codec.hpp"
#include "math/projection.hpp"
#include "protocol/protocol.hpp"
#include "net/clock.hpp"
#include "net/peer_address.hpp"
#include "net/udp_socket.hpp"
#include "secure/envelope.hpp"
#include "secure/key.hpp"
#include "session/fov_margin.hpp"
#include "session/latency_histogram.hpp"
#include "session/rate_control.hpp"
#include "session/pose_predictor.hpp"
#include "trace/visibility_tracer.hpp"

#include <array>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace dhr::server {

struct ServiceConfig {
  // The deployment key (docs/security.md): Hellos must carry its handshake tag, Welcomes carry the server's,
  // every session datagram is sealed with the session's keys, replays are dropped. std::nullopt: no
  // authentication (dhr-server --insecure); a client's authenticated Hello then gets a plain Welcome.
  std::optional<secure::Key> key;
  std::string scene_id;     // Hello's scene id must be empty, this, or a path/file name with this stem
  uint64_t scene_hash = 0;  // sent in Welcome (see scene_content_hash)
  uint32_t max_sessions = 8;
  int64_t session_timeout_ns = 5 * net::kNsPerSecond;
  int64_t heartbeat_interval_ns = net::kNsPerSecond;
  EncodeOptions encode;
  // Codec v2 (codec/codec_v2.hpp) for clients that offer it: each eye coded against the newest frame the client
  // acknowledged holding, intra when there is none and at least every v2_intra_refresh_ns. false: codec v1.
  bool codec_v2 = true;
  int64_t v2_intra_refresh_ns = 2 * net::kNsPerSecond;
  // A pose bit-identical (both eyes) to the last traced one is not traced again, except once every
  // identical_refresh_ns (so a lost shard of a still scene is repaired); 0 = never refresh.
  bool skip_identical_pose = true;
  int64_t identical_refresh_ns = net::kNsPerSecond;
  // Server-side pose prediction (server/session/include/session/pose_predictor.hpp), off by default: each eye is traced for the
  // views predicted at the pose's display time + the horizon. predict_horizon_ns < 0: automatic, the
  // session's round trip (from Heartbeat echoes) + how long the pose waited here + the session's last
  // trace-and-send time (service clock); >= 0: that fixed horizon. Shards carry the predicted views.
  // With the automatic horizon, horizon_on_frame_grid rounds it up to whole client frame periods (estimated
  // from the poses' display times): the result is displayed at the first client frame after it arrives.
  bool predict = false;
  int64_t predict_horizon_ns = -1;
  bool horizon_on_frame_grid = true;
  PosePredictorConfig predictor;
  // Adaptive traced field of view (server/session/include/session/fov_margin.hpp), off by default: each eye's traced FOV is widened
  // beyond the guard band by the recent shortfall of the traced views against the views the client displayed
  // (the horizon is the automatic one above, or predict_horizon_ns), within the session's buffer.
  FovMarginConfig adaptive_fov;
  // Per-session trace rate from the client's reports of what arrived (session/rate_control.hpp), off by
  // default; dhr-server turns it on. A capped session's datagrams wait in its pacing queue: whoever drives
  // the service must then call pace() every few milliseconds (run_serve does).
  RateControlConfig rate_control;
  // Soft levels (docs/protocol.md, "Mask layout") for clients that offer them, when the scene has a light with
  // an extent: its field is the Gray-coded level of its sampled visibility (Embree; the Vulkan tracer writes
  // level 0 or the top level for now). Off: every session gets one bit per light.
  bool soft_levels = true;
  // Reuse of traced visibility (trace/reuse/reuse_frame.hpp; Embree): each eye of a session takes whole blocks
  // and pixel-light pairs from its previous trace, pairs from the left eye's trace of the same frame (the right
  // eye) and from the newest traces of up to three other sessions. Off here; dhr-server's --reuse auto turns it on
  // where it saves time (shipped::reuse_by_default; docs/server.md, "Reuse").
  bool reuse = false;
  // Worker threads run_serve starts to trace sessions in parallel (one session per worker at a time); the
  // Vulkan tracer takes one at a time, so it is clamped to 1 there.
  uint32_t workers = 1;
  // Unsolicited replies (Bye to an unknown token, a rejected Hello, another version's Hello) are
  // limited to this many per second over all peers: no reflection flood toward a spoofed source.
  uint32_t max_unsolicited_replies_per_second = 20;
  // Token source; seeded for tests. 0: std::random_device.
  uint64_t token_seed = 0;
};

struct ServiceStats {
  // Everything that arrived, and why datagrams were dropped.
  uint64_t datagrams_received = 0;
  uint64_t datagrams_rejected = 0;  // every drop below (decode errors, unknown token, wrong peer, ...)
  DecodeErrorCounts decode_errors;  // per DecodeError code (kWrongVersion included)
  uint64_t wrong_version = 0;       // DHR datagrams of another protocol version
  uint64_t unknown_token = 0;       // well-formed, token of no session
  uint64_t wrong_peer = 0;          // known token, from an address other than the session's Hello
  uint64_t unexpected_type = 0;     // Welcome / VisibilityShard sent to the server
  // Authentication (ServiceConfig::key), each dropped before any decoding, allocation or trace:
  uint64_t auth_failed = 0;         // a tag that did not verify: forged, damaged, or another deployment key
  uint64_t replayed = 0;            // a sealed datagram whose sequence was seen (or fell behind the window)
  uint64_t unauthenticated = 0;     // a plain datagram (no tag) where the key requires one
  uint64_t hellos_replayed = 0;     // an authenticated Hello whose random was already used
  // Handshake and sessions.
  uint64_t hellos = 0;              // well-formed Hellos
  uint64_t hellos_repeated = 0;     // same address and nonce: the same Welcome again
  uint64_t hellos_rejected = 0;     // answered Bye(bad hello / unknown scene), server full included
  uint64_t sessions_opened = 0;
  uint64_t sessions_closed = 0;     // all causes below
  uint64_t sessions_timed_out = 0;
  uint64_t sessions_closed_by_peer = 0;  // client's Bye
  uint64_t sessions_replaced = 0;   // a new Hello (other nonce) from the same address
  uint64_t sessions_active = 0;
  // Poses and frames.
  uint64_t poses_received = 0;
  uint64_t poses_stale = 0;              // frame number not newer than the newest received
  uint64_t poses_superseded = 0;         // replaced by a newer pose before being traced
  uint64_t poses_skipped_identical = 0;  // identical to the last traced pose
  uint64_t frames_traced = 0;            // (session, frame) pairs traced and sent (both eyes)
  uint64_t trace_errors = 0;             // tracer threw or encoding failed (frame not sent)
  uint64_t shards_sent = 0;
  uint64_t bytes_sent = 0;               // every datagram the service sent, headers included
  uint64_t datagrams_sent = 0;
  uint64_t send_failures = 0;            // the sender refused a datagram
  uint64_t heartbeats_received = 0;
  uint64_t heartbeats_sent = 0;
  uint64_t byes_sent = 0;
  uint64_t replies_suppressed = 0;       // unsolicited replies over the rate limit
  uint64_t frames_predicted = 0;         // traced for predicted views (ServiceConfig::predict)
  uint64_t prediction_fallbacks = 0;     // the predictor fell back to the pose as sent
  double prediction_horizon_ms = 0.0;    // sum of the horizons used
  uint64_t eyes_fov_widened = 0;         // eyes traced with a FOV widened beyond the guard band (adaptive_fov)
  double fov_span_ratio = 0.0;           // sum over traced eyes (adaptive_fov) of widened / display tangent area
  uint64_t rate_decreases = 0;           // a session's trace rate capped lower after its client reported loss
  uint64_t datagrams_shed = 0;           // paced datagrams of a frame not sent before the next frame's came
  uint64_t sessions_rate_capped = 0;     // sessions whose trace rate is capped now
  uint64_t eyes_coded_v2_inter = 0;      // eyes sent with codec v2 against an acknowledged reference
  uint64_t eyes_coded_v2_intra = 0;      // eyes sent with codec v2 on their own
  uint64_t rays = 0;                     // primary and shadow rays traced
  // ServiceConfig::reuse: pixels taken whole from an earlier trace (no ray) and pixel-light pairs answered from one.
  uint64_t reused_pixels = 0;
  uint64_t reused_pairs = 0;
  // Soft levels (sessions whose layout has level fields; TraceStats' soft_* summed over traced eyes).
  uint64_t sessions_soft = 0;            // sessions opened with the soft layout (Welcome grants soft levels)
  uint64_t soft_pairs = 0;               // hit pixel x soft light
  uint64_t soft_contributing_pairs = 0;  // of those, samples taken
  uint64_t soft_refined_pairs = 0;       // of those, refined past the first samples
  uint64_t soft_shadow_rays = 0;
  // Scene time (a moving scene only: VisibilityTracer::moves()). Each traced frame moves the tracer to its scene
  // time (the pose's, plus the horizon when predicting) before both eyes are traced.
  // App-moved nodes (NodeTransform, docs/motion.md): received, accepted (applied from their scene time on), and
  // dropped (each logged, at most once a second): for a node the scene does not let move, stamped at or before the
  // newest accepted for that node, or stamped before the scene time of a pose already traced.
  uint64_t node_transforms_received = 0;
  uint64_t node_transforms_applied = 0;
  uint64_t node_transforms_dropped_unknown_node = 0;
  uint64_t node_transforms_dropped_out_of_order = 0;
  uint64_t node_transforms_dropped_late = 0;
  uint64_t frames_at_scene_time = 0;     // frames traced and sent after moving the tracer to their scene time
  double scene_update_ms = 0.0;          // their acceleration-structure updates, summed (tracer wall time)
  LatencyHistogram trace_hist;           // trace time per eye
  LatencyHistogram response_hist;        // pose received -> its frame's last datagram handed to the socket
  double trace_ms = 0.0;                 // sums over all eyes traced (tracer wall time)
  double trace_gpu_ms = 0.0;             // their GPU time where the tracer measures it (Vulkan timestamps), summed
  double encode_ms = 0.0;                // sums: light-count repacking, codec, datagram encoding and send
};

class VisibilityService {
 public:
  // `tracer`, `sender` and `clock` must outlive the service. Throws std::invalid_argument for an
  // unusable config (zero sessions, timeouts or intervals).
  VisibilityService(VisibilityTracer& tracer, const ServiceConfig& config, net::DatagramSender& sender,
                    const net::Clock& clock);
  ~VisibilityService();
  VisibilityService(const VisibilityService&) = delete;
  VisibilityService& operator=(const VisibilityService&) = delete;

  // Decodes and validates one datagram and acts on it: Hello -> Welcome or Bye, PoseUpdate -> the
  // session's pending pose (frame numbers not newer than the newest received are ignored), NodeTransform -> the
  // session's app-moved nodes (or dropped and counted, ServiceStats::node_transforms_*), Heartbeat ->
  // echoed at once (clock-offset sample for the client), Bye -> the session ends. Never throws, never
  // traces.
  void on_datagram(std::span<const uint8_t> bytes, const net::PeerAddress& from);

  // Until no session is left to trace: claims the due session with a pending pose that was traced least
  // recently and no other caller is tracing, traces both eyes of its newest pose, encodes and sends all shards
  // to its peer. Returns the number of (session, frame) pairs traced. Several threads may call it at once
  // (ServiceConfig::workers): each session is traced by one of them at a time; the tracer must then allow
  // concurrent calls (Embree does). A moving scene's frames are traced one at a time (set_scene_time, then
  // both eyes, under one lock). Never throws (tracer errors are counted).
  size_t process_pending();

  // Timeouts (Bye(timeout) once, session dropped) and a heartbeat to each session every interval.
  void tick();

  // Sends what the pacing queues of rate-capped sessions may send by now (call often: every few ms).
  void pace();

  // Bye(shutdown) to every session; all sessions are dropped. Later datagrams are handled as usual.
  void close_all(ByeReason reason = ByeReason::kShutdown);

  // Blocks until some session has a pending pose, interrupt_wait() was called, or the timeout passes
  // (real time; for the serving worker thread). True when work is pending.
  bool wait_for_pending(int64_t timeout_ns);
  void interrupt_wait();

  ServiceStats stats() const;  // thread-safe snapshot
  size_t session_count() const;
  const ServiceConfig& config() const { return config_; }

  // What a session was granted (for logs and tests); empty when the token is unknown.
  struct SessionInfo {
    uint64_t token = 0;
    net::PeerAddress peer;
    Welcome welcome;
    uint64_t newest_frame_traced = 0;
  };
  std::vector<SessionInfo> sessions() const;

  // Session opened / closed notifications (serve's log lines). Called with no lock held, on the thread
  // that caused the event.
  using SessionEvent = std::function<void(const SessionInfo& session, bool opened, ByeReason reason)>;
  void set_session_observer(SessionEvent observer);

 private:
  struct Session;
  struct Work;

  void handle_hello(const Hello& hello, const std::optional<secure::Random>& random, const net::PeerAddress& from);
  void handle_session_message(const Datagram& datagram, const net::PeerAddress& from);
  bool reject_hello(const Hello& hello, std::string& out_reason, ByeReason& out_bye) const;
  // The Welcome and the session's mask layout (soft levels when offered, enabled and the scene has soft lights).
  Welcome make_welcome(const Hello& hello, VisibilityLayout& out_layout) const;
  uint64_t new_token();
  bool allow_unsolicited_reply(int64_t now_ns);

  // Encodes into a stack buffer, protects it as the key asks and sends; returns the bytes sent (0 when
  // refused). With a key: a Welcome carries the handshake tag bound to its Hello's random; other messages
  // of a session are sealed; messages without a session carry the handshake tag bound to `bind` (the
  // rejected Hello's random, or nothing); kPlain sends without protection (Bye(auth required / failed):
  // the peer cannot verify anything from us). Any thread.
  enum class Envelope : uint8_t { kAuto, kPlain };
  // With `queue`, the protected datagram is appended there instead of being sent (pacing).
  size_t send_message(Session* session, uint64_t token, const Message& message, const net::PeerAddress& to,
                      std::span<const uint8_t> bind = {}, Envelope envelope = Envelope::kAuto,
                      std::deque<std::vector<uint8_t>>* queue = nullptr);
  bool send_bytes(Session* session, std::span<const uint8_t> bytes, const net::PeerAddress& to);
  // Checks an incoming datagram's protection (with a key) and returns the plain datagram: `bytes` itself or
  // a part of `out`. std::nullopt when it was dropped (counted; Byes telling the client why, within the
  // reply budget).
  std::optional<std::span<const uint8_t>> unwrap(std::span<const uint8_t> bytes, const net::PeerAddress& from,
                                                 std::span<uint8_t> out, std::optional<secure::Random>& hello_random);
  size_t open_sealed(std::span<const uint8_t> bytes, const net::PeerAddress& from, std::span<uint8_t> out);
  // An app's NodeTransform for session `s` (under mutex_): recorded, or dropped and counted.
  void handle_node_transform(Session& s, const NodeTransform& transform, int64_t now_ns);
  void count_drop(uint64_t ServiceStats::*counter, const char* what, const net::PeerAddress& from);
  Heartbeat make_heartbeat(Session& session, int64_t now_ns) const;
  void close_session(std::map<uint64_t, std::shared_ptr<Session>>::iterator it, bool send_bye, ByeReason reason,
                     std::vector<std::pair<SessionInfo, ByeReason>>& closed);
  void notify(const std::vector<std::pair<SessionInfo, ByeReason>>& closed, const SessionInfo* opened);
  bool trace_and_send(const Work& work);
  // One eye with ServiceConfig::reuse: traced taking from the session's and others' newest records (below).
  void trace_reusing(Session& s, size_t eye, const Camera& camera, VisibilityBuffer& out, TraceStats& stats);
  static constexpr size_t kReuseSharedSessions = 3;
  void widen_fov(Session& s, int64_t target_time_ns, std::array<View, 2>& views);
  std::vector<VisibilityShard> encode_v2(Session& s, Eye eye, const Work& work, const Camera& camera,
                                         const VisibilityBuffer& traced, uint64_t& inter_eyes, uint64_t& intra_eyes);
  std::optional<Work> claim_work();

  VisibilityTracer& tracer_;
  const ServiceConfig config_;
  net::DatagramSender& sender_;
  const net::Clock& clock_;
  const uint32_t scene_light_count_;
  const std::vector<bool> light_extents_;  // tracer_.light_extents(): which lights may get level fields
  const bool scene_moves_;                 // tracer_.moves(): frames are traced at their scene time
  // A moving scene: held from set_scene_time through both eyes' traces (the tracer is then one scene at a time).
  std::mutex tracer_mutex_;

  mutable std::mutex mutex_;  // sessions_, stats_, rng_, reply budget
  std::condition_variable work_ready_;
  bool interrupted_ = false;
  std::map<uint64_t, std::shared_ptr<Session>> sessions_;  // by token
  ServiceStats stats_;
  std::mt19937_64 rng_;
  std::optional<secure::HandshakeKey> handshake_key_;  // from config_.key
  std::vector<secure::Random> recent_hello_randoms_;   // ring of the randoms of recent accepted Hellos
  size_t next_hello_random_ = 0;
  int64_t last_auth_log_ns_ = 0;
  int64_t reply_window_start_ns_ = 0;
  uint32_t replies_in_window_ = 0;
  SessionEvent observer_;
  std::array<int64_t, kDecodeErrorCount> last_logged_ns_{};  // rate limit of drop log lines, per code
  int64_t last_node_drop_log_ns_ = 0;                          // rate limit of dropped NodeTransform lines

  // Send counters: the worker sends shards without mutex_.
  std::atomic<uint64_t> datagrams_sent_{0};
  std::atomic<uint64_t> bytes_sent_{0};
  std::atomic<uint64_t> send_failures_{0};
  std::atomic<uint64_t> shards_sent_{0};
  std::atomic<uint32_t> unsolicited_sequence_{0};

};

// Whether a Hello's scene id names the served scene: empty, equal, or a path / file name whose stem
// (directories and extension removed) equals scene_id.
bool scene_id_matches(const std::string& requested, const std::string& scene_id);

}  // namespace dhr::server
