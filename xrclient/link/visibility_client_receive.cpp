// VisibilityClient, receive side: datagram validation and dispatch, the handshake's answers, heartbeats
// (clock offset), shards into the reassembler, and publication to the per-eye LatestSlots.
#include "log/log.hpp"
#include "link/visibility_client.hpp"

#include <bit>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <variant>

namespace dhr::client {
namespace {

void add_frame_counts(ReassemblerStats& into, const ReassemblerStats& from) {
  into.frames_completed += from.frames_completed;
  into.frames_evicted += from.frames_evicted;
  into.frames_superseded += from.frames_superseded;
}

bool refuses_hello(ByeReason reason) {
  return reason == ByeReason::kBadHello || reason == ByeReason::kUnknownScene ||
         reason == ByeReason::kVersionMismatch || reason == ByeReason::kAuthRequired ||
         reason == ByeReason::kAuthFailed;
}

// A refusal the server cannot authenticate (it cannot prove a key we do not share, or it speaks another
// version): taken in the clear, while handshaking only.
bool plain_refusal(ByeReason reason, bool have_key) {
  return reason == ByeReason::kVersionMismatch ||
         (have_key ? reason == ByeReason::kAuthFailed : reason == ByeReason::kAuthRequired);
}

std::string scene_mismatch_message(uint64_t server_hash, uint64_t own_hash) {
  char text[256];
  std::snprintf(text, sizeof text,
                "the server traces another scene (hash %016llx) than this client renders (hash %016llx): give both "
                "the same --scene file and the same --lights",
                static_cast<unsigned long long>(server_hash), static_cast<unsigned long long>(own_hash));
  return text;
}

}  // namespace

void VisibilityClient::on_datagram(std::span<const uint8_t> bytes) { on_datagram(bytes, clock_.now_ns()); }

void VisibilityClient::on_datagram(std::span<const uint8_t> bytes, int64_t now) {
  const std::lock_guard lock(mutex_);
  ++stats_.datagrams_received;
  bool authenticated = false;
  if (handshake_key_) {
    const std::optional<std::span<const uint8_t>> plain = unwrap(bytes, now, authenticated);
    if (!plain) return;
    bytes = *plain;
  }
  const DecodeError error = decode_datagram(bytes, rx_);
  if (error != DecodeError::kNone) {
    ++stats_.datagrams_rejected;
    count_rejection(error, now);
    DatagramHeader header;
    if (error == DecodeError::kWrongVersion && state_ == State::kHandshaking &&
        decode_header(bytes, header) == DecodeError::kWrongVersion)
      fail("the server speaks protocol version " + std::to_string(header.version) + ", this client version " +
           std::to_string(kProtocolVersion));
    return;
  }
  if (handshake_key_ && !authenticated) {
    // In the clear with a key: only what no key can prove is taken (a refusal; a plain Welcome ends the
    // handshake with the reason).
    if (const auto* bye = std::get_if<Bye>(&rx_.message); bye && plain_refusal(bye->reason, true)) {
      handle_bye(rx_, now);
    } else if (std::holds_alternative<Welcome>(rx_.message) && state_ == State::kHandshaking &&
               std::get<Welcome>(rx_.message).client_nonce == nonce_) {
      fail("the server answered without authentication (is it running with --insecure?); this client has a "
           "key and takes no unauthenticated session", ClientFailure::kAuthentication);
    } else {
      ++stats_.datagrams_rejected;
      count_auth_drop(&ClientNetStats::unauthenticated, "a datagram without authentication", now);
    }
    return;
  }
  if (const auto* bye = std::get_if<Bye>(&rx_.message);
      !handshake_key_ && bye != nullptr && bye->reason == ByeReason::kAuthFailed) {
    ++stats_.datagrams_foreign;  // the answer to a tagged Hello: not ours (we sent no tag)
    return;
  }
  switch (message_type(rx_.message)) {
    case MessageType::kWelcome: handle_welcome(rx_, now); return;
    case MessageType::kBye: handle_bye(rx_, now); return;
    case MessageType::kHeartbeat:
    case MessageType::kVisibilityShard: break;
    case MessageType::kHello:
    case MessageType::kPoseUpdate:
    case MessageType::kNodeTransform: ++stats_.datagrams_unexpected; return;
  }
  if (state_ != State::kConnected || rx_.session_token != token_) {
    ++stats_.datagrams_foreign;
    return;
  }
  ++stats_.datagrams_handled;
  last_receive_ns_ = now;
  sequences_.add(rx_.sequence);
  if (const auto* hb = std::get_if<Heartbeat>(&rx_.message)) {
    handle_heartbeat(*hb, now);
  } else {
    handle_shard(std::get<VisibilityShard>(rx_.message), now);
  }
}

void VisibilityClient::handle_welcome(const Datagram& datagram, int64_t now) {
  const Welcome& w = std::get<Welcome>(datagram.message);
  if (state_ == State::kConnected && datagram.session_token == token_ && w.client_nonce == nonce_) {
    // The answer to a retried Hello (or a duplicate): same session, nothing changes.
    ++stats_.welcomes_repeated;
    ++stats_.datagrams_handled;
    last_receive_ns_ = now;
    sequences_.add(datagram.sequence);
    return;
  }
  if (state_ != State::kHandshaking || w.client_nonce != nonce_) {
    ++stats_.welcomes_ignored;
    ++stats_.datagrams_foreign;
    return;
  }
  ++stats_.datagrams_handled;
  if (!(w.capabilities & kCapabilityLz4RowShards)) return fail("the server does not offer the LZ4 shard codec");
  if (handshake_key_) {  // the Welcome's tag verified against this Hello's random: derive the session's keys
    keys_ = secure::derive_session_keys(*config_.key, client_random_, server_random_, datagram.session_token);
    replay_.reset();
    replay_.accept(datagram.sequence);
  }
  if ((w.capabilities & kCapabilityCodecV2) && !config_.codec_v2)
    return fail("the server granted codec v2, which this client did not offer");
  // Light slots: both ends derive them from the scene; the fields must be the same.
  if ((w.capabilities & kCapabilityLightSlots) && config_.light_slots == 0)
    return fail("the server's lights share light slots, this client's scene has at most 32 lights");
  if (config_.light_slots != 0 && !(w.capabilities & kCapabilityLightSlots))
    return fail("this scene's lights share light slots, the server sends one field per light (another scene, or a "
                "server without light slots)");
  if (config_.light_slots != 0 && w.light_count != config_.light_slots)
    return fail("the server sends " + std::to_string(w.light_count) + " fields, this scene's lights share " +
                std::to_string(config_.light_slots) + " slots");
  // The soft lights among those the server sends: the client's layout must be the server's.
  const uint32_t sent = w.light_count >= 32 ? 0xFFFFFFFFu : (1u << w.light_count) - 1u;
  const auto soft_sent = static_cast<uint32_t>(std::popcount(config_.soft_lights & sent));
  if ((w.capabilities & kCapabilitySoftLevels) && config_.soft_lights == 0)
    return fail("the server granted soft levels, which this client did not offer");
  if ((w.capabilities & kCapabilitySoftLevels) && w.soft_light_count != soft_sent)
    return fail("the server sends levels for " + std::to_string(w.soft_light_count) + " soft lights, this scene has " +
                std::to_string(soft_sent) + " among its first " + std::to_string(w.light_count));
  if (!(w.capabilities & kCapabilitySoftLevels) && soft_sent > 0)
    return fail("the server sends one bit per light, but " + std::to_string(soft_sent) +
                " of this scene's lights have an extent, which this client shades from levels (a server with "
                "--soft-levels off or an older one)");
  if (w.format().display != config_.format.display)
    return fail("the server's buffer " + std::to_string(w.buffer_width) + "x" + std::to_string(w.buffer_height) +
                " is not the eye size " + std::to_string(config_.format.display.width) + "x" +
                std::to_string(config_.format.display.height) +
                " plus its guard band " + std::to_string(w.guard_x) + "," + std::to_string(w.guard_y));
  if (config_.light_count_wanted > 0 && w.light_count > config_.light_count_wanted)
    return fail("the server sends " + std::to_string(w.light_count) + " lights, " +
                std::to_string(config_.light_count_wanted) + " were asked for");
  if (config_.scene_hash && w.scene_hash != *config_.scene_hash) {
    // Shadows traced from another scene would be shown as if they were this one's: end the session at once.
    send(Bye{ByeReason::kNormal}, datagram.session_token);
    return fail(scene_mismatch_message(w.scene_hash, *config_.scene_hash), ClientFailure::kSceneMismatch);
  }
  adopt_session(datagram, now);
}

void VisibilityClient::adopt_session(const Datagram& datagram, int64_t now) {
  const Welcome& w = std::get<Welcome>(datagram.message);
  ReassemblerConfig rc;
  rc.width = w.buffer_width;
  rc.height = w.buffer_height;
  rc.light_count = w.used_mask_bits();  // bits per mask: the reassembler and the codecs code bits
  rc.max_frames_in_flight = config_.max_frames_in_flight;
  // Codec v2 granted: keep the newest complete frames as references (the count both sides assume).
  rc.reference_frames = (w.capabilities & kCapabilityCodecV2) ? kV2ReferenceFrames : 0;
  const bool same_geometry = reassembler_ && reassembler_->config().width == rc.width &&
                             reassembler_->config().height == rc.height &&
                             reassembler_->config().light_count == rc.light_count &&
                             reassembler_->config().reference_frames == rc.reference_frames;
  if (same_geometry) {
    reassembler_->reset();
  } else {
    if (reassembler_) add_frame_counts(retired_reassembler_stats_, reassembler_->stats());
    try {
      reassembler_ = std::make_unique<VisibilityReassembler>(rc);
    } catch (const std::invalid_argument& e) {  // the decoder's ranges make this unreachable; stay safe
      return fail(std::string("unusable Welcome: ") + e.what());
    }
  }
  if (newest_requested_) reassembler_->set_newest_requested_frame(*newest_requested_);
  token_ = datagram.session_token;
  welcome_ = w;
  state_ = State::kConnected;
  last_receive_ns_ = now;
  last_heartbeat_sent_ns_.reset();
  peer_heartbeat_.reset();
  clock_sync_.reset();
  sequences_.restart();
  sequences_.add(datagram.sequence);
  ++stats_.sessions_started;
  log::info("visibility client: session %016llx: %ux%u per eye (guard %u,%u), %u lights, scene hash %016llx",
            static_cast<unsigned long long>(token_), w.buffer_width, w.buffer_height, w.guard_x, w.guard_y,
            w.light_count, static_cast<unsigned long long>(w.scene_hash));
  // App-moved nodes: the new session's server has none of them yet (docs/motion.md).
  for (const auto& [node, newest] : sent_transforms_)
    for (const std::optional<NodeTransform>& t : newest)
      if (t && send(*t, token_)) ++stats_.node_transforms_resent;
}

void VisibilityClient::handle_bye(const Datagram& datagram, int64_t now) {
  const ByeReason reason = std::get<Bye>(datagram.message).reason;
  const bool ours = state_ == State::kConnected && datagram.session_token == token_;
  const bool refusal = datagram.session_token == 0 && state_ == State::kHandshaking && refuses_hello(reason);
  // A token-0 Bye(unknown session) answers a datagram whose token the server no longer knows.
  const bool lost_session =
      datagram.session_token == 0 && state_ == State::kConnected && reason == ByeReason::kUnknownSession;
  if (!ours && !refusal && !lost_session) {
    ++stats_.datagrams_foreign;
    return;
  }
  ++stats_.datagrams_handled;
  ++stats_.byes_received;
  if (ours) sequences_.add(datagram.sequence);
  if (reason == ByeReason::kAuthFailed)
    return fail("the server rejected this client's key (authentication failed): the server and the client need "
                "the same key file", ClientFailure::kAuthentication);
  if (reason == ByeReason::kAuthRequired)
    return fail("the server requires authentication: give the deployment's key with --key-file FILE", ClientFailure::kAuthentication);
  if (refuses_hello(reason)) return fail(std::string("the server refused the Hello: ") + to_string(reason));
  restart_session(now, to_string(reason));
}

void VisibilityClient::handle_heartbeat(const Heartbeat& hb, int64_t now) {
  ++stats_.heartbeats_received;
  stats_.last_server_heartbeat = hb;
  peer_heartbeat_ = hb;
  peer_heartbeat_receive_ns_ = now;
  if (hb.echo_time_ns > 0) clock_sync_.add_echo(hb.echo_time_ns, hb.echo_delay_ns, hb.send_time_ns, now);
}

void VisibilityClient::handle_shard(const VisibilityShard& shard, int64_t now) {
  ++stats_.shards_received;
  const auto eye_index = static_cast<size_t>(shard.eye);
  if (eye_index <= 1 && shard.buffer_width == reassembler_->config().width &&
      shard.buffer_height == reassembler_->config().height &&
      (!newest_requested_ || shard.frame_number <= *newest_requested_)) {
    // A newer frame starts: the eye's newest frame so far, still incomplete, is published as it is
    // (before the insert, which may evict it).
    const ReassembledFrame* previous = reassembler_->latest(shard.eye);
    if (previous && !previous->complete() && shard.frame_number > previous->visibility.frame_number)
      publish(shard.eye, *previous, now);
  }
  const InsertResult result = reassembler_->insert(shard);
  switch (result.status) {
    case InsertStatus::kAccepted:
    case InsertStatus::kCompleted: {
      ++stats_.shards_accepted;
      EyeState& eye = eyes_[eye_index];
      eye.last_shard_ns = now;
      auto& newest = stats_.newest_frame_received[eye_index];
      if (!newest || shard.frame_number > *newest) newest = shard.frame_number;
      if (result.status == InsertStatus::kCompleted) {
        stats_.newest_frame_complete[eye_index] = shard.frame_number;
        publish(shard.eye, *reassembler_->latest_complete(shard.eye), now);
        responses_.on_eye_complete(shard.frame_number, shard.eye, now);
      }
      break;
    }
    case InsertStatus::kDuplicate: ++stats_.shards_duplicate; break;
    case InsertStatus::kLate: ++stats_.shards_late; break;
    case InsertStatus::kRejected:
      ++stats_.shards_rejected;
      count_rejection(result.error, now);
      break;
  }
}

void VisibilityClient::publish(Eye eye, const ReassembledFrame& frame, int64_t now) {
  EyeState& state = eyes_[static_cast<size_t>(eye)];
  const uint64_t number = frame.visibility.frame_number;
  const bool newer = !state.published_frame || number > *state.published_frame;
  const bool more = state.published_frame && number == *state.published_frame &&
                    frame.pixels_received > state.published_pixels;
  if (!newer && !more) return;  // frame numbers never go back
  // The one copy on the way to the renderer: the reassembler keeps receiving into its own slot. The
  // destination is recycled storage (no allocation in steady state).
  VisibilityFrame& out = state.slot.write_buffer();
  out = frame.visibility;
  out.received_ns = now;
  const bool complete = out.complete;
  state.slot.publish();  // `out` belongs to the reader from here on
  state.published_frame = number;
  state.published_pixels = frame.pixels_received;
  ++(complete ? stats_.frames_published_complete : stats_.frames_published_partial);
}

void VisibilityClient::publish_quiet_partials(int64_t now) {
  for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
    const EyeState& state = eyes_[static_cast<size_t>(eye)];
    const ReassembledFrame* frame = reassembler_->latest(eye);
    if (frame && !frame->complete() && state.last_shard_ns != 0 &&
        now - state.last_shard_ns >= config_.partial_publish_after_ns)
      publish(eye, *frame, now);
  }
}

std::optional<std::span<const uint8_t>> VisibilityClient::unwrap(std::span<const uint8_t> bytes, int64_t now,
                                                                 bool& authenticated) {
  authenticated = false;
  // Short, another version, or plain: the decoder judges it (and what a plain one may say, after decoding).
  const uint16_t flags = secure::datagram_flags(bytes);
  if (bytes.size() < kHeaderSize || bytes[4] != kProtocolVersion || flags == 0) return bytes;
  if (flags == secure::kFlagAuthenticated) {
    // Bound to this Hello's random (Welcome, a refusal), or to nothing (Bye(unknown session): the server lost
    // the session, e.g. it restarted).
    auto v = handshake_key_->verify(bytes, rx_bytes_, client_random_);
    if (!v && bytes.size() > 5 && bytes[5] == static_cast<uint8_t>(MessageType::kBye)) {
      v = handshake_key_->verify(bytes, rx_bytes_);
    }
    if (!v) {
      ++stats_.datagrams_rejected;
      count_auth_drop(&ClientNetStats::auth_failed, "a handshake tag that does not verify", now);
      return std::nullopt;
    }
    server_random_ = v->random;
    authenticated = true;
    return std::span<const uint8_t>(rx_bytes_.data(), v->size);
  }
  if (flags == secure::kFlagSealed) {
    uint64_t token = 0;
    for (size_t i = 0; i < 8; ++i) token |= uint64_t{bytes[8 + i]} << (8 * i);
    if (state_ != State::kConnected || token != token_) {
      ++stats_.datagrams_foreign;
      return std::nullopt;
    }
    const std::optional<size_t> n = secure::open(keys_.server_to_client, bytes, rx_bytes_);
    if (!n) {
      ++stats_.datagrams_rejected;
      count_auth_drop(&ClientNetStats::auth_failed, "a sealed datagram that does not open", now);
      return std::nullopt;
    }
    if (!replay_.accept(secure::datagram_sequence(bytes))) {
      ++stats_.datagrams_rejected;
      count_auth_drop(&ClientNetStats::replayed, "a replayed datagram", now);
      return std::nullopt;
    }
    authenticated = true;
    return std::span<const uint8_t>(rx_bytes_.data(), *n);
  }
  return bytes;  // unknown flags: the decoder rejects them (reserved field)
}

void VisibilityClient::count_auth_drop(uint64_t ClientNetStats::*counter, const char* what, int64_t now) {
  ++(stats_.*counter);
  if (last_auth_log_ns_ != 0 && now - last_auth_log_ns_ < net::kNsPerSecond) return;
  last_auth_log_ns_ = now == 0 ? 1 : now;
  log::warn("visibility client: dropped %s (auth failed %llu, replayed %llu, unauthenticated %llu so far)", what,
            static_cast<unsigned long long>(stats_.auth_failed), static_cast<unsigned long long>(stats_.replayed),
            static_cast<unsigned long long>(stats_.unauthenticated));
}

void VisibilityClient::count_rejection(DecodeError error, int64_t now) {
  stats_.rejections.add(error);
  const auto code = static_cast<size_t>(error) < kDecodeErrorCount ? static_cast<size_t>(error) : 0;
  // At most one line per code and second: a flood of garbage must not flood the log.
  if (last_log_ns_[code] != 0 && now - last_log_ns_[code] < net::kNsPerSecond) return;
  last_log_ns_[code] = now == 0 ? 1 : now;
  log::warn("visibility client: dropped a datagram or shard: %s (%llu so far)", to_string(error),
            static_cast<unsigned long long>(stats_.rejections[error]));
}

}  // namespace dhr::client
