// VisibilityClient: the headset's side of the DHR protocol (docs/protocol.md), independent of the
// transport: datagrams come in through on_datagram() (a socket's receive thread, or a simulated link's
// delivery loop) and go out through a net::DatagramSender (a socket, an impaired socket, a SimulatedLink).
//
// Threads: on_datagram() runs on the receive thread; tick(), send_pose() and take_newest() on the render
// thread; stats() anywhere. One mutex guards the session and the reassembler (held for one datagram's
// decode at most); the render loop gets visibility through one LatestSlot per eye, so take_newest() never
// waits for the receive side.
//
// Publication (per eye, newest wins, frame numbers never go back): a frame is published when it completes;
// an incomplete frame is published (usable row by row, see row_valid) when shards of a newer frame start
// arriving, or when nothing arrived for it for partial_publish_after_ns; a frame published incomplete is
// published again when more of it arrives and it goes quiet again, or when it completes.
// docs/network.md ("Client side") describes the counters and the response-time measurement.
#pragma once
#include "protocol/protocol.hpp"
#include "codec/reassembly.hpp"
#include "codec/visibility_frame.hpp"
#include "visibility/visibility.hpp"
#include "math/projection.hpp"
#include "net/clock.hpp"
#include "net/clock_sync.hpp"
#include "net/latest_slot.hpp"
#include "link/response_tracker.hpp"
#include "link/sequence_tracker.hpp"
#include "net/udp_socket.hpp"
#include "secure/envelope.hpp"
#include "secure/key.hpp"
#include "secure/replay_window.hpp"

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dhr::client {

// Why a client failed for good (VisibilityClient::failed()).
enum class ClientFailure : uint8_t {
  kNone,
  kOther,           // no Welcome in time, the server refused the Hello, an unusable Welcome
  kAuthentication,  // the server refused the key or requires one, or did not authenticate itself
  kSceneMismatch,   // the Welcome names another scene than the client's (VisibilityClientConfig::scene_hash)
};

struct VisibilityClientConfig {
  // The deployment key (docs/security.md): the Hello carries its handshake tag, the Welcome must carry the
  // server's, every session datagram is sealed and replays are dropped. std::nullopt: no authentication.
  std::optional<secure::Key> key;
  // Displayed size per eye (>= 1x1) and guard band per side, as the Hello asks for them; the server may grant
  // a smaller guard band (Welcome).
  TracedFormat format;
  uint8_t light_count_wanted = 0;  // 0 = as many as the scene has (up to 32)
  std::string scene_id;            // empty = the server's default scene
  // The hash of the scene this client renders (scene_content_hash, --lights applied): a Welcome that names
  // another scene fails the client for good (ClientFailure::kSceneMismatch). std::nullopt: not checked.
  std::optional<uint64_t> scene_hash;
  bool codec_v2 = true;            // offer codec v2 (the server decides; v1 is always offered)
  // Bit i: this client's light i has an extent (render::soft_light_mask of the scene's VisibilityLayout). Non-zero:
  // soft levels are offered, and the Welcome must grant them for exactly the soft lights among the lights it sends
  // (the client shades those lights from level fields; one bit per light would be read as levels).
  uint32_t soft_lights = 0;
  // The fields of a scene whose lights share light slots (LightSlots::slot_count; soft_lights then marks soft
  // fields); 0: one field per light. Non-zero: light slots are offered, and the Welcome must grant them with
  // exactly this many fields; zero: a Welcome granting them is refused.
  uint32_t light_slots = 0;
  int64_t hello_retry_ns = 250 * net::kNsPerMs;
  int64_t hello_give_up_ns = 5 * net::kNsPerSecond;
  // Offline mode: past hello_give_up_ns keep sending Hello, the interval doubling from hello_retry_ns up to
  // hello_backoff_max_ns, instead of failing (the client shades with its own shadow maps meanwhile). A client
  // that once had a session does so whatever this says (its server restarted or the network came back). A
  // server that refuses the Hello still ends the session for good.
  bool keep_retrying = false;
  int64_t hello_backoff_max_ns = 2 * net::kNsPerSecond;
  size_t max_frames_in_flight = 4;  // reassembler frames per eye, 2..64
  // Publish an incomplete frame once nothing arrived for it this long: the rest is probably lost.
  int64_t partial_publish_after_ns = 20 * net::kNsPerMs;
  uint64_t nonce_seed = 1;     // Hello nonces are drawn from this (deterministic runs)
  net::PeerAddress server;     // passed to DatagramSender::send_to (ignored by senders bound to the server)
  size_t response_history = ResponseTracker::kDefaultCapacity;  // frames whose response time is kept
};

struct ClientNetStats {
  // Datagrams in: received = rejected + foreign + unexpected + handled.
  uint64_t datagrams_received = 0;    // handed to on_datagram
  uint64_t datagrams_rejected = 0;    // failed decoding: by code in `rejections`
  uint64_t datagrams_foreign = 0;     // valid, but not for the current session (token, state)
  uint64_t datagrams_unexpected = 0;  // valid, but a message the client never takes (Hello, PoseUpdate)
  uint64_t datagrams_handled = 0;
  DecodeErrorCounts rejections;       // decode errors of datagrams, plus shards the reassembler rejected
  // With a key, dropped before decoding (part of datagrams_rejected):
  uint64_t auth_failed = 0;      // a tag that did not verify (forged, damaged, another key, another Hello)
  uint64_t replayed = 0;         // a sealed datagram whose sequence was seen (or fell behind the window)
  uint64_t unauthenticated = 0;  // a plain datagram the key does not allow
  // From the server's sequence numbers (current session's datagrams): exact within an 8192 window.
  uint64_t server_datagrams_unique = 0;
  uint64_t server_datagrams_duplicate = 0;
  uint64_t server_datagrams_missing = 0;  // gaps so far (lost, or still in flight)
  // Datagrams out.
  uint64_t datagrams_sent = 0;
  uint64_t send_failures = 0;  // the sender refused (queue full, not running) or encoding failed
  // Session.
  uint64_t hellos_sent = 0;
  uint64_t hellos_backed_off = 0;   // sent past hello_give_up_ns (keep_retrying)
  uint64_t welcomes_ignored = 0;   // nonce not the outstanding one
  uint64_t welcomes_repeated = 0;  // answers to a retried Hello after the session started
  uint64_t sessions_started = 0;   // Welcomes adopted
  uint64_t sessions_restarted = 0; // back to Hello after a timeout or Bye
  uint64_t session_timeouts = 0;
  uint64_t byes_received = 0;
  uint64_t heartbeats_sent = 0;
  uint64_t heartbeats_received = 0;
  std::optional<Heartbeat> last_server_heartbeat;  // the server's own counters
  // Poses.
  uint64_t poses_sent = 0;
  uint64_t poses_not_connected = 0;  // send_pose() before the handshake finished
  uint64_t poses_refused = 0;        // frame number not increasing, or negative display or scene time
  // App-moved nodes (send_node_transform).
  uint64_t node_transforms_sent = 0;
  uint64_t node_transforms_not_connected = 0;  // before the handshake finished
  uint64_t node_transforms_refused = 0;        // no receiver would accept it (non-finite, scale <= 0, ...)
  uint64_t node_transforms_resent = 0;         // the newest two per node, again to a new session's server
  // Shards (of the current session).
  uint64_t shards_received = 0;
  uint64_t shards_accepted = 0;
  uint64_t shards_late = 0;
  uint64_t shards_duplicate = 0;
  uint64_t shards_rejected = 0;  // by code in `rejections` (session mismatch, inconsistent, future frame...)
  // Frames.
  uint64_t frames_completed = 0;
  uint64_t frames_evicted = 0;     // incomplete, pushed out by newer frames
  uint64_t frames_superseded = 0;  // incomplete, released when a newer frame completed
  uint64_t frames_published_complete = 0;
  uint64_t frames_published_partial = 0;
  uint64_t frames_overwritten = 0;  // published, replaced by a newer one before take_newest() saw it
  uint64_t frames_taken = 0;
  std::array<std::optional<uint64_t>, 2> newest_frame_received;  // per eye, any accepted shard
  std::array<std::optional<uint64_t>, 2> newest_frame_complete;
  size_t reassembler_memory_bytes = 0;
  // Clock offset (server - client) from Heartbeat echoes.
  bool clock_offset_valid = false;
  int64_t clock_offset_ns = 0;
  int64_t clock_rtt_ns = 0;
  int64_t clock_uncertainty_ns = 0;
  uint64_t clock_samples = 0;
  uint64_t clock_samples_rejected = 0;
  // Response time: pose sent -> both eyes complete (client clock).
  ResponseSummary response;
};

class VisibilityClient {
 public:
  // `to_server` and `clock` must outlive the client. Throws std::invalid_argument for a bad config.
  VisibilityClient(const VisibilityClientConfig& config, net::DatagramSender& to_server, const net::Clock& clock);
  ~VisibilityClient();
  VisibilityClient(const VisibilityClient&) = delete;
  VisibilityClient& operator=(const VisibilityClient&) = delete;

  // Receive side, one thread at a time. Never throws on any input (bad input is counted and dropped).
  void on_datagram(std::span<const uint8_t> bytes);
  void on_datagram(std::span<const uint8_t> bytes, int64_t receive_ns);  // receive time, client clock

  // Render thread: the first call sends Hello; then Hello retries and give-up, heartbeats, the session
  // timeout, and publication of incomplete frames that went quiet.
  void tick();

  bool connected() const;
  std::optional<Welcome> welcome() const;  // the current session's, while connected
  bool failed() const;                     // terminal: gave up on Hello, or the server refused it
  std::string failure() const;             // one line, empty unless failed()
  // failed() because of authentication: the server refused the key or requires one, or answered without
  // authenticating itself to a client with a key.
  bool failed_authentication() const;
  ClientFailure failure_kind() const;  // kNone unless failed()

  // Render thread: sends a PoseUpdate (when connected; frame numbers strictly increasing) and remembers
  // its send time. False when not sent (not connected, frame not newer, negative time, send refused).
  bool send_pose(const FramePose& pose);

  // Render thread: an application moved glTF node `node`: from `scene_time_ns` on its local transform is `trs`
  // (docs/motion.md, "App-moved nodes"). Sends a NodeTransform when connected and returns the transform exactly as
  // the server decodes it (rotation and scale rounded to the wire's f32): the caller records that one in its own
  // NodeOverrides (rendering, the warp's motion rule) so that both ends hold the same bits. std::nullopt when not
  // sent (not connected, not a valid transform, send refused). Which nodes may move is the server's to check.
  // The newest two per node (of the first kMaxRememberedNodes nodes) are sent again when a new session starts
  // (after a timeout or Bye the server's copy went with the old session), so the server extrapolates as the
  // client does.
  std::optional<NodeTransform> send_node_transform(uint32_t node, int64_t scene_time_ns, const Trs& trs);
  static constexpr size_t kMaxRememberedNodes = 4096;

  // Render thread: the newest visibility of that eye published since the last call, swapped into `out`
  // (no copy; out's old storage is recycled). False, leaving `out` untouched, when nothing newer arrived.
  // Never blocks.
  bool take_newest(Eye eye, VisibilityFrame& out);

  // Pose sent -> both eyes of that frame complete, client clock; nullopt when unknown or not (yet)
  // complete. The newest response_history frames are remembered.
  std::optional<int64_t> response_ns(uint64_t frame) const;

  // Sends Bye(normal) when connected and stops the session (tick() no longer sends anything).
  void close();

  ClientNetStats stats() const;
  // The reassembler's bound: (2 * max_frames_in_flight + 1) buffers plus per-slot bookkeeping.
  size_t memory_bound_bytes() const;

 private:
  enum class State : uint8_t { kIdle, kHandshaking, kConnected, kFailed, kClosed };
  struct EyeState {
    net::LatestSlot<VisibilityFrame> slot;
    std::optional<uint64_t> published_frame;
    size_t published_pixels = 0;
    int64_t last_shard_ns = 0;
  };

  void start_handshake(int64_t now);
  void send_hello(int64_t now);
  void send_heartbeat(int64_t now);
  bool send(const Message& message, uint64_t token);
  void fail(std::string reason, ClientFailure kind = ClientFailure::kOther);
  void restart_session(int64_t now, const char* why);

  void handle_welcome(const Datagram& datagram, int64_t now);
  void handle_bye(const Datagram& datagram, int64_t now);
  void handle_heartbeat(const Heartbeat& heartbeat, int64_t now);
  void handle_shard(const VisibilityShard& shard, int64_t now);
  void adopt_session(const Datagram& datagram, int64_t now);
  void publish(Eye eye, const ReassembledFrame& frame, int64_t now);
  void publish_quiet_partials(int64_t now);
  void count_rejection(DecodeError error, int64_t now);
  // With a key: checks the datagram's protection and returns the plain datagram (`bytes` itself when it is not
  // protected, else opened into rx_bytes_); std::nullopt when dropped (counted). `authenticated`: it carried
  // a valid tag or seal.
  std::optional<std::span<const uint8_t>> unwrap(std::span<const uint8_t> bytes, int64_t now, bool& authenticated);
  void count_auth_drop(uint64_t ClientNetStats::*counter, const char* what, int64_t now);

  const VisibilityClientConfig config_;
  net::DatagramSender& sender_;
  const net::Clock& clock_;

  mutable std::mutex mutex_;
  State state_ = State::kIdle;
  std::string failure_;
  ClientFailure failure_kind_ = ClientFailure::kNone;
  uint64_t rng_state_;
  uint64_t nonce_ = 0;
  uint64_t token_ = 0;
  std::optional<Welcome> welcome_;
  int64_t handshake_start_ns_ = 0;
  int64_t last_hello_ns_ = 0;
  int64_t hello_interval_ns_ = 0;  // hello_retry_ns, doubled per Hello once backing off
  int64_t last_receive_ns_ = 0;  // newest valid datagram of the session
  std::optional<int64_t> last_heartbeat_sent_ns_;
  std::optional<Heartbeat> peer_heartbeat_;  // newest from the server, for the echo
  int64_t peer_heartbeat_receive_ns_ = 0;
  uint32_t tx_sequence_ = 0;
  std::optional<uint64_t> newest_requested_;
  std::unique_ptr<VisibilityReassembler> reassembler_;
  ReassemblerStats retired_reassembler_stats_;  // of reassemblers replaced by a new session's geometry
  std::array<EyeState, 2> eyes_;
  net::ClockOffsetEstimator clock_sync_;
  ResponseTracker responses_;
  SequenceTracker sequences_;
  // App-moved nodes: the newest two transforms sent per node ([1] the newer), for a new session.
  std::map<uint32_t, std::array<std::optional<NodeTransform>, 2>> sent_transforms_;
  ClientNetStats stats_;
  std::array<int64_t, kDecodeErrorCount> last_log_ns_{};
  Datagram rx_;                                    // decode target (a shard is ~1.3 KB)
  std::array<uint8_t, kMaxDatagramSize> tx_{};     // encode buffer
  std::array<uint8_t, kMaxDatagramSize> rx_bytes_{};  // an opened datagram
  std::optional<secure::HandshakeKey> handshake_key_;  // from config_.key
  secure::Random client_random_{};   // this handshake's (the same on every retry of its Hello)
  secure::Random server_random_{};   // from the newest verified handshake datagram
  secure::SessionKeys keys_;         // the session's, from the Welcome
  secure::ReplayWindow replay_;      // of the session's sealed datagrams
  int64_t last_auth_log_ns_ = 0;
  std::atomic<uint64_t> frames_taken_{0};
};

}  // namespace dhr::client
