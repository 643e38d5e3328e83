// VisibilityService: authentication (docs/security.md). Outgoing messages are protected as the key asks
// (send_message); incoming datagrams are checked before anything else looks at them (unwrap): a Hello's
// handshake tag, a session datagram's seal and its sequence against the session's replay window.
#include "session/service_session.hpp"

#include "log/log.hpp"

namespace dhr::server {

using namespace session_detail;

size_t VisibilityService::send_message(Session* session, uint64_t token, const Message& message,
                                       const net::PeerAddress& to, std::span<const uint8_t> bind,
                                       Envelope envelope, std::deque<std::vector<uint8_t>>* queue) {
  Datagram datagram;
  datagram.session_token = token;
  const uint64_t sequence = session ? session->next_sequence.fetch_add(1, std::memory_order_relaxed)
                                     : unsolicited_sequence_.fetch_add(1, std::memory_order_relaxed);
  datagram.sequence = static_cast<uint32_t>(sequence);
  datagram.message = message;
  std::array<uint8_t, kMaxDatagramSize> plain;
  const size_t plain_size = encode_datagram(datagram, plain);
  std::array<uint8_t, kMaxDatagramSize> sealed;
  std::span<const uint8_t> bytes(plain.data(), plain_size);
  if (plain_size > 0 && config_.key && envelope == Envelope::kAuto) {
    const bool welcome = std::holds_alternative<Welcome>(message);
    if (session != nullptr && session->secure && !welcome) {
      // The sequence is the seal's nonce: never reuse one under a key. A session that used them all sends
      // nothing more (its client times out and starts a new session with new keys).
      const size_t n = sequence >= 0xFFFFFFFFu ? 0 : secure::seal(session->keys.server_to_client, bytes, sealed);
      bytes = std::span<const uint8_t>(sealed.data(), n);
    } else {
      const secure::Random random = session != nullptr && session->secure ? session->server_random : secure::Random{};
      const std::span<const uint8_t> bound =
          session != nullptr && session->secure ? std::span<const uint8_t>(session->client_random) : bind;
      const size_t n = handshake_key_->authenticate(plain, plain_size, random, bound);
      bytes = std::span<const uint8_t>(plain.data(), n);
    }
  }
  if (queue != nullptr && !bytes.empty()) {
    queue->emplace_back(bytes.begin(), bytes.end());
    return bytes.size();
  }
  return send_bytes(session, bytes, to) ? bytes.size() : 0;
}

bool VisibilityService::send_bytes(Session* session, std::span<const uint8_t> bytes, const net::PeerAddress& to) {
  if (bytes.empty() || !sender_.send_to(bytes, to)) {
    send_failures_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  datagrams_sent_.fetch_add(1, std::memory_order_relaxed);
  bytes_sent_.fetch_add(bytes.size(), std::memory_order_relaxed);
  if (session) session->datagrams_sent.fetch_add(1, std::memory_order_relaxed);
  return true;
}

void VisibilityService::count_drop(uint64_t ServiceStats::*counter, const char* what, const net::PeerAddress& from) {
  ++stats_.datagrams_received;
  ++stats_.datagrams_rejected;
  ++(stats_.*counter);
  const int64_t now = clock_.now_ns();
  if (last_auth_log_ns_ == 0 || now - last_auth_log_ns_ >= net::kNsPerSecond) {
    last_auth_log_ns_ = now == 0 ? 1 : now;
    log::warn("dropped a datagram from %s: %s (auth failed %llu, replayed %llu, unauthenticated %llu so far)",
              from.to_string().c_str(), what, static_cast<unsigned long long>(stats_.auth_failed),
              static_cast<unsigned long long>(stats_.replayed), static_cast<unsigned long long>(stats_.unauthenticated));
  }
}

std::optional<std::span<const uint8_t>> VisibilityService::unwrap(std::span<const uint8_t> bytes,
                                                                  const net::PeerAddress& from, std::span<uint8_t> out,
                                                                  std::optional<secure::Random>& hello_random) {
  // Another protocol version (or no DHR datagram at all): the decoder drops it, answering another version's
  // Hello with Bye(version mismatch), whether a key is set or not.
  if (bytes.size() < kHeaderSize || bytes[4] != kProtocolVersion) return bytes;
  const uint16_t flags = secure::datagram_flags(bytes);
  const bool is_hello = bytes.size() > 5 && bytes[5] == static_cast<uint8_t>(MessageType::kHello) &&
                        bytes[4] == kProtocolVersion;
  if (!handshake_key_) {
    // No key: a client's authenticated Hello is read without its trailer (the plain Welcome tells the client
    // that this server does not authenticate); anything else goes to the decoder as it is.
    if (flags == secure::kFlagAuthenticated && is_hello && bytes.size() >= kHeaderSize + secure::kHandshakeTrailerSize &&
        bytes.size() <= kMaxDatagramSize) {
      const size_t n = bytes.size() - secure::kHandshakeTrailerSize;
      std::copy(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n), out.begin());
      out[6] = out[7] = 0;
      return std::span<const uint8_t>(out.data(), n);
    }
    return bytes;
  }
  auto span_of = [&](size_t n) { return std::optional<std::span<const uint8_t>>(std::span<const uint8_t>(out.data(), n)); };
  if (flags == secure::kFlagSealed) {
    const size_t n = open_sealed(bytes, from, out);
    return n == 0 ? std::nullopt : span_of(n);
  }
  std::lock_guard lock(mutex_);
  if (flags == secure::kFlagAuthenticated && is_hello) {
    const std::optional<secure::HandshakeKey::Verified> v = handshake_key_->verify(bytes, out);
    if (v) {
      hello_random = v->random;
      return span_of(v->size);
    }
    count_drop(&ServiceStats::auth_failed, "a Hello whose tag does not verify (another key?)", from);
    if (allow_unsolicited_reply(clock_.now_ns()) &&
        send_message(nullptr, 0, Bye{ByeReason::kAuthFailed}, from, {}, Envelope::kPlain))
      ++stats_.byes_sent;
    return std::nullopt;
  }
  if (flags == secure::kFlagAuthenticated) {
    count_drop(&ServiceStats::auth_failed, "a handshake tag on a message that takes none", from);
    return std::nullopt;
  }
  count_drop(&ServiceStats::unauthenticated, "no authentication (the client has no key?)", from);
  if (is_hello && flags == 0 && allow_unsolicited_reply(clock_.now_ns()) &&
      send_message(nullptr, 0, Bye{ByeReason::kAuthRequired}, from, {}, Envelope::kPlain))
    ++stats_.byes_sent;
  return std::nullopt;
}

size_t VisibilityService::open_sealed(std::span<const uint8_t> bytes, const net::PeerAddress& from,
                                      std::span<uint8_t> out) {
  DatagramHeader header;
  std::array<uint8_t, kHeaderSize> clear{};
  if (bytes.size() >= kHeaderSize) {  // decode_header checks the reserved field: read it with flags cleared
    std::copy(bytes.begin(), bytes.begin() + kHeaderSize, clear.begin());
    clear[6] = clear[7] = 0;
  }
  std::lock_guard lock(mutex_);
  if (bytes.size() < kHeaderSize || decode_header(clear, header) != DecodeError::kNone) {
    count_drop(&ServiceStats::auth_failed, "a sealed datagram with a bad header", from);
    return 0;
  }
  const auto it = sessions_.find(header.session_token);
  if (it == sessions_.end()) {
    ++stats_.datagrams_received;
    ++stats_.datagrams_rejected;
    ++stats_.unknown_token;
    // Tell the client to start over: a reply with the handshake tag, bound to nothing (a replay of it can only
    // make a client of that token say Hello again).
    if (header.type != MessageType::kBye && allow_unsolicited_reply(clock_.now_ns()) &&
        send_message(nullptr, header.session_token, Bye{ByeReason::kUnknownSession}, from))
      ++stats_.byes_sent;
    return 0;
  }
  Session& s = *it->second;
  if (s.peer != from || !s.secure) {  // possibly spoofed: no state change, no reply
    ++stats_.datagrams_received;
    ++stats_.datagrams_rejected;
    ++stats_.wrong_peer;
    return 0;
  }
  const std::optional<size_t> n = secure::open(s.keys.client_to_server, bytes, out);
  if (!n) {
    ++s.datagrams_rejected;
    count_drop(&ServiceStats::auth_failed, "a sealed datagram that does not open", from);
    return 0;
  }
  if (!s.replay.accept(header.sequence)) {
    ++s.datagrams_rejected;
    count_drop(&ServiceStats::replayed, "a replayed datagram", from);
    return 0;
  }
  return *n;
}

}  // namespace dhr::server
