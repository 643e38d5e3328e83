// VisibilityService: datagram dispatch, session messages, timeouts, heartbeats, statistics. The
// handshake is in visibility_service_hello.cpp, tracing in visibility_service_trace.cpp.
#include "session/service_session.hpp"

#include "log/log.hpp"

#include <chrono>
#include <stdexcept>

namespace dhr::server {

using namespace session_detail;

VisibilityService::VisibilityService(VisibilityTracer& tracer, const ServiceConfig& config,
                                     net::DatagramSender& sender, const net::Clock& clock)
    : tracer_(tracer),
      config_(config),
      sender_(sender),
      clock_(clock),
      scene_light_count_(std::min(tracer.light_count(), kMaxLights)),
      light_extents_(tracer.light_extents()),
      scene_moves_(tracer.moves()) {
  if (config_.max_sessions == 0) throw std::invalid_argument("visibility service: max_sessions must be >= 1");
  if (config_.session_timeout_ns <= 0 || config_.heartbeat_interval_ns <= 0)
    throw std::invalid_argument("visibility service: session timeout and heartbeat interval must be > 0");
  if (config_.identical_refresh_ns < 0) throw std::invalid_argument("visibility service: identical_refresh_ns < 0");
  if (config_.predict) PosePredictor check(config_.predictor);  // throws std::invalid_argument when unusable
  if (config_.adaptive_fov.enabled) FovMarginTracker check(config_.adaptive_fov);  // the same
  uint64_t seed = config_.token_seed;
  if (seed == 0) {
    std::random_device rd;
    seed = (static_cast<uint64_t>(rd()) << 32) ^ rd();
  }
  rng_.seed(seed);
  reply_window_start_ns_ = clock_.now_ns();
  if (config_.key) handshake_key_.emplace(*config_.key);
}

VisibilityService::~VisibilityService() = default;

void VisibilityService::set_session_observer(SessionEvent observer) {
  std::lock_guard lock(mutex_);
  observer_ = std::move(observer);
}

bool VisibilityService::allow_unsolicited_reply(int64_t now_ns) {
  if (now_ns - reply_window_start_ns_ >= net::kNsPerSecond || now_ns < reply_window_start_ns_) {
    reply_window_start_ns_ = now_ns;
    replies_in_window_ = 0;
  }
  if (replies_in_window_ >= config_.max_unsolicited_replies_per_second) {
    ++stats_.replies_suppressed;
    return false;
  }
  ++replies_in_window_;
  return true;
}

Heartbeat VisibilityService::make_heartbeat(Session& session, int64_t now_ns) const {
  Heartbeat hb;
  hb.send_time_ns = std::max<int64_t>(now_ns, 0);
  if (session.have_peer_heartbeat) {
    hb.echo_time_ns = session.peer_heartbeat_send_ns;
    hb.echo_delay_ns = std::max<int64_t>(now_ns - session.peer_heartbeat_receive_ns, 0);
  }
  hb.newest_frame = session.newest_frame_traced;
  hb.datagrams_sent = clamp_u32(session.datagrams_sent.load(std::memory_order_relaxed) + 1);  // this one too
  hb.datagrams_received = clamp_u32(session.datagrams_received);
  hb.datagrams_rejected = clamp_u32(session.datagrams_rejected);
  hb.frames_done = clamp_u32(session.frames_done.load(std::memory_order_relaxed));
  hb.frames_dropped = clamp_u32(session.frames_dropped);
  return hb;
}

void VisibilityService::close_session(std::map<uint64_t, std::shared_ptr<Session>>::iterator it, bool send_bye,
                                      ByeReason reason, std::vector<std::pair<SessionInfo, ByeReason>>& closed) {
  Session& s = *it->second;
  if (send_bye && send_message(&s, s.token, Bye{reason}, s.peer) > 0) ++stats_.byes_sent;
  s.open.store(false, std::memory_order_release);
  closed.emplace_back(s.info(), reason);
  ++stats_.sessions_closed;
  sessions_.erase(it);
}

void VisibilityService::notify(const std::vector<std::pair<SessionInfo, ByeReason>>& closed,
                               const SessionInfo* opened) {
  SessionEvent observer;
  {
    std::lock_guard lock(mutex_);
    observer = observer_;
  }
  if (!observer) return;
  for (const auto& [info, reason] : closed) observer(info, false, reason);
  if (opened) observer(*opened, true, ByeReason::kNormal);
}

void VisibilityService::on_datagram(std::span<const uint8_t> wire, const net::PeerAddress& from) {
  try {
    // Authentication first: nothing is decoded, allocated or traced for a datagram that fails it.
    std::array<uint8_t, kMaxDatagramSize> plain;
    std::optional<secure::Random> hello_random;
    const std::optional<std::span<const uint8_t>> unwrapped = unwrap(wire, from, plain, hello_random);
    if (!unwrapped) return;
    const std::span<const uint8_t> bytes = *unwrapped;
    Datagram datagram;
    const DecodeError error = decode_datagram(bytes, datagram);
    if (error != DecodeError::kNone) {
      std::lock_guard lock(mutex_);
      ++stats_.datagrams_received;
      ++stats_.datagrams_rejected;
      stats_.decode_errors.add(error);
      // Counted, logged at most once per second per code, no reply: except another version's Hello
      // (byte 5 is the type in every version), which learns why it gets no Welcome.
      const int64_t now = clock_.now_ns();
      int64_t& logged = last_logged_ns_[static_cast<size_t>(error) % kDecodeErrorCount];
      if (logged == 0 || now - logged >= net::kNsPerSecond) {
        logged = now == 0 ? 1 : now;
        log::info("dropped a datagram from %s: %s (%llu so far)", from.to_string().c_str(), to_string(error),
                  static_cast<unsigned long long>(stats_.decode_errors[error]));
      }
      if (error == DecodeError::kWrongVersion) {
        ++stats_.wrong_version;
        if (bytes.size() > 5 && bytes[5] == static_cast<uint8_t>(MessageType::kHello) &&
            allow_unsolicited_reply(now) && send_message(nullptr, 0, Bye{ByeReason::kVersionMismatch}, from))
          ++stats_.byes_sent;
      }
      return;
    }
    if (const auto* hello = std::get_if<Hello>(&datagram.message)) {
      handle_hello(*hello, hello_random, from);
    } else {
      handle_session_message(datagram, from);
    }
  } catch (const std::exception& e) {
    log::error("visibility service: datagram from %s: %s", from.to_string().c_str(), e.what());  // bad_alloc
  }
}

void VisibilityService::handle_session_message(const Datagram& datagram, const net::PeerAddress& from) {
  std::vector<std::pair<SessionInfo, ByeReason>> closed;
  {
    std::lock_guard lock(mutex_);
    const int64_t now = clock_.now_ns();
    ++stats_.datagrams_received;
    auto it = sessions_.find(datagram.session_token);
    if (it == sessions_.end()) {
      ++stats_.datagrams_rejected;
      ++stats_.unknown_token;
      // Tell the client to start over (never answer a Bye with a Bye).
      if (!std::holds_alternative<Bye>(datagram.message) && allow_unsolicited_reply(now) &&
          send_message(nullptr, datagram.session_token, Bye{ByeReason::kUnknownSession}, from))
        ++stats_.byes_sent;
      return;
    }
    Session& s = *it->second;
    if (s.peer != from) {  // possibly spoofed: no state change, no reply
      ++stats_.datagrams_rejected;
      ++stats_.wrong_peer;
      return;
    }
    if (const auto* pose = std::get_if<PoseUpdate>(&datagram.message)) {
      s.last_receive_ns = now;
      ++s.datagrams_received;
      ++stats_.poses_received;
      if (s.have_frame && pose->frame <= s.newest_frame_received) {
        ++stats_.poses_stale;
        return;
      }
      s.have_frame = true;
      s.newest_frame_received = pose->frame;
      if (s.pending) {
        ++stats_.poses_superseded;
        ++s.frames_dropped;
      }
      s.pending = *pose;
      s.pending_receive_ns = now;
      for (size_t e = 0; e < 2; ++e) {  // acknowledgements only move forward
        const std::optional<uint64_t> held = pose->held_frame(e);
        if (held && (!s.codec[e].acked || *held > *s.codec[e].acked)) s.codec[e].acked = held;
      }
      if (config_.predict || config_.adaptive_fov.enabled) s.predictor.add(pose->display_time_ns, pose->views);
      if (config_.adaptive_fov.enabled) s.fov_margin.observed(pose->display_time_ns, pose->views);
      work_ready_.notify_one();
    } else if (const auto* hb = std::get_if<Heartbeat>(&datagram.message)) {
      s.last_receive_ns = now;
      ++s.datagrams_received;
      ++stats_.heartbeats_received;
      s.have_peer_heartbeat = true;
      s.peer_heartbeat_send_ns = hb->send_time_ns;
      s.peer_heartbeat_receive_ns = now;
      if (hb->echo_time_ns != 0) s.offset.add_echo(hb->echo_time_ns, hb->echo_delay_ns, hb->send_time_ns, now);
      const uint64_t decreases = s.rate.decreases();
      s.rate.on_report(now, hb->datagrams_received, s.datagrams_sent.load(std::memory_order_relaxed),
                       s.frames_done.load(std::memory_order_relaxed));
      stats_.rate_decreases += s.rate.decreases() - decreases;
      // Echo at once (a tight clock sample for the client), at most 4 times per heartbeat interval.
      if (!s.echoed || now - s.last_echo_ns >= config_.heartbeat_interval_ns / 4) {
        s.echoed = true;
        s.last_echo_ns = now;
        s.last_heartbeat_sent_ns = now;
        if (send_message(&s, s.token, make_heartbeat(s, now), s.peer)) ++stats_.heartbeats_sent;
      }
    } else if (const auto* transform = std::get_if<NodeTransform>(&datagram.message)) {
      s.last_receive_ns = now;
      ++s.datagrams_received;
      handle_node_transform(s, *transform, now);
    } else if (std::holds_alternative<Bye>(datagram.message)) {
      ++s.datagrams_received;
      ++stats_.sessions_closed_by_peer;
      close_session(it, false, std::get<Bye>(datagram.message).reason, closed);
    } else {  // Welcome, VisibilityShard: server-to-client messages
      ++s.datagrams_rejected;
      ++stats_.datagrams_rejected;
      ++stats_.unexpected_type;
      return;
    }
  }
  if (!closed.empty()) notify(closed, nullptr);
}

void VisibilityService::tick() {
  std::vector<std::pair<SessionInfo, ByeReason>> closed;
  {
    std::lock_guard lock(mutex_);
    const int64_t now = clock_.now_ns();
    for (auto it = sessions_.begin(); it != sessions_.end();) {
      auto next = std::next(it);
      Session& s = *it->second;
      if (now - s.last_receive_ns > config_.session_timeout_ns) {
        ++stats_.sessions_timed_out;
        close_session(it, true, ByeReason::kTimeout, closed);
      } else if (now - s.last_heartbeat_sent_ns >= config_.heartbeat_interval_ns) {
        s.last_heartbeat_sent_ns = now;
        if (send_message(&s, s.token, make_heartbeat(s, now), s.peer)) ++stats_.heartbeats_sent;
      }
      it = next;
    }
  }
  if (!closed.empty()) notify(closed, nullptr);
}

void VisibilityService::pace() {
  std::vector<std::pair<std::shared_ptr<Session>, std::optional<double>>> sessions;
  {
    std::lock_guard lock(mutex_);
    sessions.reserve(sessions_.size());
    for (const auto& [token, s] : sessions_) sessions.emplace_back(s, s->rate.pacing_dps());
  }
  const int64_t now = clock_.now_ns();
  for (const auto& [s, dps] : sessions) {
    std::lock_guard pace_lock(s->pace_mutex);
    if (s->paced.empty()) {
      s->pace_credit = 1.0;  // the next frame's first datagram leaves at once
      s->pace_last_ns = now;
      continue;
    }
    if (dps) {
      s->pace_credit = std::min(s->pace_credit + *dps * static_cast<double>(now - s->pace_last_ns) * 1e-9, 2.0);
    } else {
      s->pace_credit = static_cast<double>(s->paced.size());  // the cap is gone: everything now
    }
    s->pace_last_ns = now;
    while (s->pace_credit >= 1.0 && !s->paced.empty()) {
      if (s->open.load(std::memory_order_acquire)) send_bytes(s.get(), s->paced.front(), s->peer);
      s->paced.pop_front();
      s->pace_credit -= 1.0;
    }
  }
}

void VisibilityService::close_all(ByeReason reason) {
  std::vector<std::pair<SessionInfo, ByeReason>> closed;
  {
    std::lock_guard lock(mutex_);
    while (!sessions_.empty()) close_session(sessions_.begin(), true, reason, closed);
  }
  if (!closed.empty()) notify(closed, nullptr);
}

bool VisibilityService::wait_for_pending(int64_t timeout_ns) {
  std::unique_lock lock(mutex_);
  // Pending and due (a session whose trace rate is capped waits for its next slot).
  const auto any_due = [&] {
    const int64_t now = clock_.now_ns();
    for (const auto& [token, s] : sessions_)
      if (s->pending && !s->busy && s->rate.due(now, s->last_trace_ns)) return true;
    return false;
  };
  const int64_t now = clock_.now_ns();
  for (const auto& [token, s] : sessions_) {
    // A session another worker is tracing is not due (and must not make this wait spin).
    if (s->pending && !s->busy) {
      timeout_ns = std::min(timeout_ns, std::max<int64_t>(s->rate.next_due_ns(s->last_trace_ns) - now, 0));
    }
  }
  work_ready_.wait_for(lock, std::chrono::nanoseconds(timeout_ns), [&] { return interrupted_ || any_due(); });
  interrupted_ = false;
  return any_due();
}

void VisibilityService::interrupt_wait() {
  {
    std::lock_guard lock(mutex_);
    interrupted_ = true;
  }
  work_ready_.notify_all();
}

ServiceStats VisibilityService::stats() const {
  std::lock_guard lock(mutex_);
  ServiceStats out = stats_;
  out.sessions_active = sessions_.size();
  for (const auto& [token, s] : sessions_) out.sessions_rate_capped += s->rate.cap_fps() ? 1 : 0;
  out.datagrams_sent = datagrams_sent_.load(std::memory_order_relaxed);
  out.bytes_sent = bytes_sent_.load(std::memory_order_relaxed);
  out.send_failures = send_failures_.load(std::memory_order_relaxed);
  out.shards_sent = shards_sent_.load(std::memory_order_relaxed);
  return out;
}

size_t VisibilityService::session_count() const {
  std::lock_guard lock(mutex_);
  return sessions_.size();
}

std::vector<VisibilityService::SessionInfo> VisibilityService::sessions() const {
  std::lock_guard lock(mutex_);
  std::vector<SessionInfo> out;
  for (const auto& [token, s] : sessions_) out.push_back(s->info());
  return out;
}

}  // namespace dhr::server
