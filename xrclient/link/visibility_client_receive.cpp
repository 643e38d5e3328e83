// VisibilityClient, receive side: datagram validation and dispatch, the handshake's answers, heartbeats
// (clock offset), shards into the reassembler, and publication to the per-eye LatestSlots.
#include "log/log.hpp"
#include "link/visibility_client.hpp"

#include <stdexcept>
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
         reason == ByeReason::kVersionMismatch;
}

}  // namespace

void VisibilityClient::on_datagram(std::span<const uint8_t> bytes) { on_datagram(bytes, clock_.now_ns()); }

void VisibilityClient::on_datagram(std::span<const uint8_t> bytes, int64_t now) {
  const std::lock_guard lock(mutex_);
  ++stats_.datagrams_received;
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
  switch (message_type(rx_.message)) {
    case MessageType::kWelcome: handle_welcome(rx_, now); return;
    case MessageType::kBye: handle_bye(rx_, now); return;
    case MessageType::kHeartbeat:
    case MessageType::kVisibilityShard: break;
    case MessageType::kHello:
    case MessageType::kPoseUpdate: ++stats_.datagrams_unexpected; return;
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
  if ((w.capabilities & kCapabilityCodecV2) && !config_.codec_v2)
    return fail("the server granted codec v2, which this client did not offer");
  if (w.format().display != config_.format.display)
    return fail("the server's buffer " + std::to_string(w.buffer_width) + "x" + std::to_string(w.buffer_height) +
                " is not the eye size " + std::to_string(config_.format.display.width) + "x" +
                std::to_string(config_.format.display.height) +
                " plus its guard band " + std::to_string(w.guard_x) + "," + std::to_string(w.guard_y));
  if (config_.light_count_wanted > 0 && w.light_count > config_.light_count_wanted)
    return fail("the server sends " + std::to_string(w.light_count) + " lights, " +
                std::to_string(config_.light_count_wanted) + " were asked for");
  adopt_session(datagram, now);
}

void VisibilityClient::adopt_session(const Datagram& datagram, int64_t now) {
  const Welcome& w = std::get<Welcome>(datagram.message);
  ReassemblerConfig rc;
  rc.width = w.buffer_width;
  rc.height = w.buffer_height;
  rc.light_count = w.light_count;
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
