// VisibilityClient: configuration, the session state machine (Hello, retries, timeouts, heartbeats) and
// the render-thread API. The receive path (datagram dispatch, shards, publication) is in
// visibility_client_receive.cpp.
#include "link/visibility_client.hpp"

#include "codec/codec.hpp"
#include "log/log.hpp"

#include <algorithm>
#include <stdexcept>

namespace dhr::client {
namespace {

// splitmix64: a small, seedable generator for Hello nonces (not security: the token is the server's).
uint64_t next_random(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

void validate_config(const VisibilityClientConfig& c) {
  auto bad = [](const std::string& what) { throw std::invalid_argument("visibility client: " + what); };
  if (c.format.display.width < 1 || c.format.display.height < 1) bad("eye size must be at least 1x1");
  const uint64_t traced_w = uint64_t{c.format.display.width} + 2u * uint64_t{c.format.guard.x};
  const uint64_t traced_h = uint64_t{c.format.display.height} + 2u * uint64_t{c.format.guard.y};
  if (traced_w > kMaxBufferDimension || traced_h > kMaxBufferDimension)
    bad("eye size plus guard band exceeds " + std::to_string(kMaxBufferDimension) + " pixels");
  if (c.light_count_wanted > kMaxLights) bad("at most " + std::to_string(kMaxLights) + " lights");
  if (c.scene_id.size() > kMaxSceneIdLength) bad("scene id longer than " + std::to_string(kMaxSceneIdLength));
  for (const char ch : c.scene_id)
    if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7F) bad("scene id contains a control character");
  if (c.hello_retry_ns <= 0 || c.hello_give_up_ns < c.hello_retry_ns) bad("need 0 < hello retry <= give-up time");
  if (c.max_frames_in_flight < 2 || c.max_frames_in_flight > 64) bad("max_frames_in_flight must be in 2..64");
  if (c.partial_publish_after_ns < 0) bad("partial_publish_after_ns must be >= 0");
}

}  // namespace

VisibilityClient::VisibilityClient(const VisibilityClientConfig& config, net::DatagramSender& to_server,
                                   const net::Clock& clock)
    : config_(config),
      sender_(to_server),
      clock_(clock),
      rng_state_(config.nonce_seed),
      responses_(config.response_history) {
  validate_config(config_);
  if (config_.key) handshake_key_.emplace(*config_.key);
}

VisibilityClient::~VisibilityClient() = default;

bool VisibilityClient::send(const Message& message, uint64_t token) {
  size_t size = encode_datagram(Datagram{token, tx_sequence_, message}, tx_);
  std::array<uint8_t, kMaxDatagramSize> sealed;
  const uint8_t* bytes = tx_.data();
  if (size > 0 && handshake_key_) {
    if (std::holds_alternative<Hello>(message)) {
      size = handshake_key_->authenticate(tx_, size, client_random_);
    } else if (tx_sequence_ == 0xFFFFFFFFu) {
      // The sequence is the seal's nonce and must never repeat under a session's key: a session this long
      // starts over (new keys, the sequence from 0).
      restart_session(clock_.now_ns(), "2^32 - 1 datagrams sent under its keys");
      return false;
    } else {
      size = secure::seal(keys_.client_to_server, std::span(tx_).first(size), sealed);
      bytes = sealed.data();
    }
  }
  if (size == 0 || !sender_.send_to(std::span<const uint8_t>(bytes, size), config_.server)) {
    ++stats_.send_failures;
    return false;
  }
  ++tx_sequence_;
  ++stats_.datagrams_sent;
  return true;
}

void VisibilityClient::start_handshake(int64_t now) {
  state_ = State::kHandshaking;
  token_ = 0;
  welcome_.reset();
  do nonce_ = next_random(rng_state_);
  while (nonce_ == 0);
  if (handshake_key_) {
    client_random_ = secure::random_bytes();
    tx_sequence_ = 0;  // new session keys: the nonces start over
  }
  handshake_start_ns_ = now;
  hello_interval_ns_ = config_.hello_retry_ns;
  send_hello(now);
}

void VisibilityClient::send_hello(int64_t now) {
  Hello hello;
  hello.client_nonce = nonce_;  // the same nonce on every retry: the server's answer is idempotent
  hello.eye_width = static_cast<uint16_t>(config_.format.display.width);  // validated: <= kMaxBufferDimension
  hello.eye_height = static_cast<uint16_t>(config_.format.display.height);
  hello.guard_x = static_cast<uint16_t>(config_.format.guard.x);
  hello.guard_y = static_cast<uint16_t>(config_.format.guard.y);
  hello.light_count_wanted = config_.light_count_wanted;
  hello.scene_id = config_.scene_id;
  // Soft levels: offered when the scene has lights with an extent, whose fields the client shades from levels.
  hello.capabilities = kCapabilityLz4RowShards | (config_.codec_v2 ? kCapabilityCodecV2 : 0u) |
                       (config_.soft_lights != 0 ? kCapabilitySoftLevels : 0u) |
                       (config_.light_slots != 0 ? kCapabilityLightSlots : 0u);
  last_hello_ns_ = now;
  if (send(hello, 0)) ++stats_.hellos_sent;
}

void VisibilityClient::send_heartbeat(int64_t now) {
  Heartbeat hb;
  hb.send_time_ns = now;
  if (peer_heartbeat_) {
    hb.echo_time_ns = peer_heartbeat_->send_time_ns;
    hb.echo_delay_ns = now - peer_heartbeat_receive_ns_;
  }
  for (size_t e = 0; e < 2; ++e)
    if (stats_.newest_frame_complete[e]) hb.newest_frame = std::max(hb.newest_frame, *stats_.newest_frame_complete[e]);
  hb.datagrams_sent = static_cast<uint32_t>(stats_.datagrams_sent + 1);  // this one included
  hb.datagrams_received = static_cast<uint32_t>(stats_.datagrams_received);
  hb.datagrams_rejected = static_cast<uint32_t>(stats_.datagrams_rejected);
  const ReassemblerStats r = reassembler_ ? reassembler_->stats() : ReassemblerStats{};
  hb.frames_done = static_cast<uint32_t>(retired_reassembler_stats_.frames_completed + r.frames_completed);
  hb.frames_dropped = static_cast<uint32_t>(retired_reassembler_stats_.frames_evicted + r.frames_evicted);
  last_heartbeat_sent_ns_ = now;
  if (send(hb, token_)) ++stats_.heartbeats_sent;
}

void VisibilityClient::fail(std::string reason, ClientFailure kind) {
  if (state_ == State::kFailed) return;
  // A session that ends is an error worth a line; a handshake that fails is reported by whoever waits for it
  // (the setup throws, the frame loop warns once).
  if (state_ == State::kConnected) {
    log::error("visibility client: %s", reason.c_str());
  } else {
    log::info("visibility client: %s", reason.c_str());
  }
  failure_kind_ = kind;
  failure_ = std::move(reason);
  state_ = State::kFailed;
  token_ = 0;
  welcome_.reset();
}

void VisibilityClient::restart_session(int64_t now, const char* why) {
  log::warn("visibility client: session %016llx ended (%s); sending Hello again",
            static_cast<unsigned long long>(token_), why);
  ++stats_.sessions_restarted;
  if (reassembler_) reassembler_->reset();
  for (EyeState& eye : eyes_) eye.last_shard_ns = 0;
  peer_heartbeat_.reset();
  last_heartbeat_sent_ns_.reset();
  start_handshake(now);
}

void VisibilityClient::tick() {
  const std::lock_guard lock(mutex_);
  const int64_t now = clock_.now_ns();
  switch (state_) {
    case State::kIdle:
      start_handshake(now);
      break;
    case State::kHandshaking: {
      const bool past_give_up = now - handshake_start_ns_ >= config_.hello_give_up_ns;
      // Once a session existed the server is worth waiting for (it restarted, the network came back): only a
      // client that never reached one gives up, unless it keeps retrying anyway.
      if (past_give_up && !config_.keep_retrying && stats_.sessions_started == 0) {
        fail("no Welcome from the server after " + std::to_string(stats_.hellos_sent) + " Hello(s) in " +
             std::to_string((now - handshake_start_ns_) / net::kNsPerMs) + " ms");
      } else if (now - last_hello_ns_ >= hello_interval_ns_) {
        if (past_give_up) {  // offline: back off
          if (hello_interval_ns_ == config_.hello_retry_ns) {  // the first backoff of this handshake
            log::warn("visibility client: no Welcome in %lld ms; retrying with backoff",
                      static_cast<long long>(config_.hello_give_up_ns / net::kNsPerMs));
          }
          hello_interval_ns_ = std::min(hello_interval_ns_ * 2, std::max(config_.hello_backoff_max_ns,
                                                                         config_.hello_retry_ns));
          ++stats_.hellos_backed_off;
        }
        send_hello(now);
      }
      break;
    }
    case State::kConnected: {
      const int64_t timeout_ns = int64_t{welcome_->session_timeout_ms} * net::kNsPerMs;
      if (now - last_receive_ns_ >= timeout_ns) {
        ++stats_.session_timeouts;
        restart_session(now, "nothing received within the session timeout");
        break;
      }
      const int64_t interval_ns = int64_t{welcome_->heartbeat_interval_ms} * net::kNsPerMs;
      if (!last_heartbeat_sent_ns_ || now - *last_heartbeat_sent_ns_ >= interval_ns) send_heartbeat(now);
      publish_quiet_partials(now);
      break;
    }
    case State::kFailed:
    case State::kClosed:
      break;
  }
}

bool VisibilityClient::connected() const {
  const std::lock_guard lock(mutex_);
  return state_ == State::kConnected;
}

std::optional<Welcome> VisibilityClient::welcome() const {
  const std::lock_guard lock(mutex_);
  return state_ == State::kConnected ? welcome_ : std::nullopt;
}

bool VisibilityClient::failed() const {
  const std::lock_guard lock(mutex_);
  return state_ == State::kFailed;
}

std::string VisibilityClient::failure() const {
  const std::lock_guard lock(mutex_);
  return failure_;
}

bool VisibilityClient::failed_authentication() const { return failure_kind() == ClientFailure::kAuthentication; }

ClientFailure VisibilityClient::failure_kind() const {
  const std::lock_guard lock(mutex_);
  return state_ == State::kFailed ? failure_kind_ : ClientFailure::kNone;
}

bool VisibilityClient::send_pose(const FramePose& pose) {
  const std::lock_guard lock(mutex_);
  if (state_ != State::kConnected) {
    ++stats_.poses_not_connected;
    return false;
  }
  if ((newest_requested_ && pose.frame <= *newest_requested_) || pose.display_time_ns < 0 || pose.scene_time_ns < 0) {
    ++stats_.poses_refused;
    return false;
  }
  // Requested from now on even if the send is refused locally: a shard for it is then merely unexpected.
  newest_requested_ = pose.frame;
  reassembler_->set_newest_requested_frame(pose.frame);
  PoseUpdate update;
  static_cast<FramePose&>(update) = pose;  // frame, display time, views and the display's scene time
  // Acknowledgements for codec v2: the newest complete frame kept as a reference, per eye.
  for (size_t e = 0; e < 2; ++e) {
    const std::optional<uint64_t> held = reassembler_->newest_reference(static_cast<Eye>(e));
    if (held && *held < pose.frame && pose.frame - *held <= 65535)
      update.held_distance[e] = static_cast<uint16_t>(pose.frame - *held);
  }
  const int64_t now = clock_.now_ns();
  if (!send(update, token_)) return false;
  ++stats_.poses_sent;
  responses_.on_pose_sent(pose.frame, now);
  return true;
}

std::optional<NodeTransform> VisibilityClient::send_node_transform(uint32_t node, int64_t scene_time_ns,
                                                                  const Trs& trs) {
  const std::lock_guard lock(mutex_);
  if (state_ != State::kConnected) {
    ++stats_.node_transforms_not_connected;
    return std::nullopt;
  }
  const std::optional<NodeTransform> decoded = node_transform_as_decoded(NodeTransform{node, scene_time_ns, trs});
  if (!decoded) {
    ++stats_.node_transforms_refused;
    return std::nullopt;
  }
  if (!send(*decoded, token_)) return std::nullopt;
  ++stats_.node_transforms_sent;
  const auto remembered = sent_transforms_.find(node);
  if (remembered != sent_transforms_.end()) {
    remembered->second = {remembered->second[1], decoded};
  } else if (sent_transforms_.size() < kMaxRememberedNodes) {
    sent_transforms_.emplace(node, std::array<std::optional<NodeTransform>, 2>{std::nullopt, decoded});
  }
  return decoded;
}

bool VisibilityClient::take_newest(Eye eye, VisibilityFrame& out) {
  const auto index = static_cast<size_t>(eye);
  if (index > 1) return false;
  // Reader side of the slot: no lock (the writer publishes under mutex_, the reader never waits).
  if (!eyes_[index].slot.take(out)) return false;
  frames_taken_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

std::optional<int64_t> VisibilityClient::response_ns(uint64_t frame) const {
  const std::lock_guard lock(mutex_);
  return responses_.response_ns(frame);
}

void VisibilityClient::close() {
  const std::lock_guard lock(mutex_);
  if (state_ == State::kConnected) send(Bye{ByeReason::kNormal}, token_);
  if (state_ != State::kFailed) state_ = State::kClosed;
}

ClientNetStats VisibilityClient::stats() const {
  const std::lock_guard lock(mutex_);
  ClientNetStats s = stats_;
  s.server_datagrams_unique = sequences_.unique();
  s.server_datagrams_duplicate = sequences_.duplicates();
  s.server_datagrams_missing = sequences_.missing();
  ReassemblerStats r = retired_reassembler_stats_;
  if (reassembler_) {
    const ReassemblerStats& now = reassembler_->stats();
    r.frames_completed += now.frames_completed;
    r.frames_evicted += now.frames_evicted;
    r.frames_superseded += now.frames_superseded;
    s.reassembler_memory_bytes = reassembler_->memory_bytes();
  }
  s.frames_completed = r.frames_completed;
  s.frames_evicted = r.frames_evicted;
  s.frames_superseded = r.frames_superseded;
  s.frames_overwritten = eyes_[0].slot.overwritten_count() + eyes_[1].slot.overwritten_count();
  s.frames_taken = frames_taken_.load(std::memory_order_relaxed);
  s.clock_offset_valid = clock_sync_.has_estimate();
  s.clock_offset_ns = clock_sync_.offset_ns();
  s.clock_rtt_ns = clock_sync_.rtt_ns();
  s.clock_uncertainty_ns = clock_sync_.uncertainty_ns();
  s.clock_samples = clock_sync_.accepted_count();
  s.clock_samples_rejected = clock_sync_.rejected_count();
  s.response = responses_.summary();
  return s;
}

size_t VisibilityClient::memory_bound_bytes() const {
  const std::lock_guard lock(mutex_);
  if (!reassembler_) return 0;
  const ReassemblerConfig& c = reassembler_->config();
  const size_t buffer = size_t{c.width} * c.height * mask_bytes(mask_width_for_light_count(c.light_count));
  // Per slot: the buffer, row_valid (1 B/row), received pixels per row (4 B/row), one flag per shard
  // index, and the received ranges (<= one per shard, 8 B each; reserved 64, grown by doubling).
  const size_t shards = reassembler_->max_shards_per_frame();
  const size_t per_slot = buffer + size_t{c.height} * 5 + shards + std::max<size_t>(64, 2 * shards) * 8;
  return 2 * c.max_frames_in_flight * per_slot + buffer + 2 * c.reference_frames * buffer;  // + v2 references
}

}  // namespace dhr::client
