// VisibilityService: the handshake (Hello -> Welcome or Bye) and scene id matching.
#include "session/service_session.hpp"

#include "log/log.hpp"

#include <algorithm>

namespace dhr::server {

using namespace session_detail;

bool scene_id_matches(const std::string& requested, const std::string& scene_id) {
  if (requested.empty() || requested == scene_id) return true;
  std::string stem = requested;
  if (const size_t slash = stem.find_last_of("/\\"); slash != std::string::npos) stem = stem.substr(slash + 1);
  if (const size_t dot = stem.find_last_of('.'); dot != std::string::npos && dot > 0) stem = stem.substr(0, dot);
  return !stem.empty() && stem == scene_id;
}

uint64_t VisibilityService::new_token() {
  for (;;) {
    const uint64_t token = rng_();
    if (token != 0 && !sessions_.count(token)) return token;
  }
}

bool VisibilityService::reject_hello(const Hello& hello, std::string& out_reason, ByeReason& out_bye) const {
  out_bye = ByeReason::kBadHello;
  if (!(hello.capabilities & kCapabilityLz4RowShards)) {
    out_reason = "the client lacks the LZ4 shard codec";
    return true;
  }
  const auto size_ok = [](uint32_t eye, uint32_t guard) { return eye >= 1 && eye + 2 * guard <= kMaxBufferDimension; };
  if (!size_ok(hello.eye_width, hello.guard_x) || !size_ok(hello.eye_height, hello.guard_y)) {
    out_reason = "eye size plus guard band out of range";
    return true;
  }
  if (hello.light_count_wanted > kMaxLights) {
    out_reason = "more than 32 lights wanted";
    return true;
  }
  if (const LightSlots* slots = tracer_.light_slots()) {
    if (!(hello.capabilities & kCapabilityLightSlots)) {
      out_reason = "the scene's " + std::to_string(slots->light_count()) +
                   " lights share light slots, which the client did not offer";
      return true;
    }
    if (hello.light_count_wanted != 0 && hello.light_count_wanted < slots->slot_count()) {
      out_reason = "a scene whose lights share light slots is served whole (" + std::to_string(slots->slot_count()) +
                   " fields), not its first " + std::to_string(hello.light_count_wanted);
      return true;
    }
  }
  if (!scene_id_matches(hello.scene_id, config_.scene_id)) {
    out_bye = ByeReason::kUnknownScene;
    out_reason = "scene '" + hello.scene_id + "' is not served (serving '" + config_.scene_id + "')";
    return true;
  }
  return false;
}

Welcome VisibilityService::make_welcome(const Hello& hello, VisibilityLayout& out_layout) const {
  Welcome w;
  w.client_nonce = hello.client_nonce;
  w.capabilities = kCapabilityLz4RowShards |
                   (config_.codec_v2 && (hello.capabilities & kCapabilityCodecV2) ? kCapabilityCodecV2 : 0u) |
                   (tracer_.light_slots() ? kCapabilityLightSlots : 0u);  // reject_hello checked the offer
  w.scene_hash = config_.scene_hash;
  const uint32_t wanted = hello.light_count_wanted == 0 ? scene_light_count_ : hello.light_count_wanted;
  w.light_count = static_cast<uint8_t>(std::min(wanted, scene_light_count_));
  // Soft levels only when the client offered them and some light of the session gets a level field; otherwise
  // one bit per light (a soft light traced to its centre), exactly the masks of a client without the capability.
  out_layout = VisibilityLayout::hard(w.light_count);
  if (config_.soft_levels && (hello.capabilities & kCapabilitySoftLevels) && !light_extents_.empty()) {
    const VisibilityLayout soft = layout_for_lights(light_extents_, w.light_count);
    if (soft.any_soft()) out_layout = soft;
  }
  uint32_t soft_lights = 0;
  for (uint32_t i = 0; i < out_layout.light_count; ++i) soft_lights += out_layout.is_soft(i) ? 1u : 0u;
  if (soft_lights > 0) w.capabilities |= kCapabilitySoftLevels;
  w.soft_light_count = static_cast<uint8_t>(soft_lights);
  w.mask_bits = out_layout.mask_width();
  w.buffer_width = static_cast<uint16_t>(hello.eye_width + 2u * hello.guard_x);
  w.buffer_height = static_cast<uint16_t>(hello.eye_height + 2u * hello.guard_y);
  w.guard_x = hello.guard_x;
  w.guard_y = hello.guard_y;
  w.heartbeat_interval_ms = clamp_ms_u16(config_.heartbeat_interval_ns);
  w.session_timeout_ms = static_cast<uint32_t>(
      std::clamp<int64_t>(config_.session_timeout_ns / net::kNsPerMs, 1, 0xFFFFFFFFll));
  return w;
}

void VisibilityService::handle_hello(const Hello& hello, const std::optional<secure::Random>& random,
                                     const net::PeerAddress& from) {
  std::vector<std::pair<SessionInfo, ByeReason>> closed;
  std::optional<SessionInfo> opened;
  {
    std::lock_guard lock(mutex_);
    const int64_t now = clock_.now_ns();
    ++stats_.datagrams_received;
    ++stats_.hellos;
    for (auto it = sessions_.begin(); it != sessions_.end(); ++it) {
      Session& s = *it->second;
      if (s.peer != from) continue;
      if (s.hello.client_nonce == hello.client_nonce && (!random || *random == s.client_random)) {
        // Idempotent: the same Welcome again (a retried Hello carries the same nonce and random).
        ++stats_.hellos_repeated;
        ++s.datagrams_received;
        s.last_receive_ns = now;
        send_message(&s, s.token, s.welcome, from);
        return;
      }
      ++stats_.sessions_replaced;  // the client started over from the same socket
      close_session(it, false, ByeReason::kNormal, closed);
      break;
    }
    if (random && std::find(recent_hello_randoms_.begin(), recent_hello_randoms_.end(), *random) !=
                      recent_hello_randoms_.end()) {
      // An authenticated Hello seen before, not from its session's address: a replay. No session, no reply.
      ++stats_.hellos_replayed;
      ++stats_.datagrams_rejected;
      return;
    }
    std::string reason;
    ByeReason bye = ByeReason::kBadHello;
    bool rejected = reject_hello(hello, reason, bye);
    if (!rejected && sessions_.size() >= config_.max_sessions) {
      rejected = true;
      reason = "server full (" + std::to_string(config_.max_sessions) + " sessions)";
    }
    if (rejected) {
      ++stats_.hellos_rejected;
      if (allow_unsolicited_reply(now)) {  // the log follows the reply budget: a flood logs little
        log::info("rejected Hello from %s: %s", from.to_string().c_str(), reason.c_str());
        const std::span<const uint8_t> bind = random ? std::span<const uint8_t>(*random) : std::span<const uint8_t>{};
        if (send_message(nullptr, 0, Bye{bye}, from, bind)) ++stats_.byes_sent;
      }
    } else {
      auto session = std::make_shared<Session>();
      session->token = new_token();
      session->peer = from;
      session->hello = hello;
      session->welcome = make_welcome(hello, session->layout);
      if (session->layout.any_soft()) ++stats_.sessions_soft;
      if (random && config_.key) {
        session->secure = true;
        session->client_random = *random;
        session->server_random = secure::random_bytes();
        session->keys = secure::derive_session_keys(*config_.key, session->client_random, session->server_random,
                                                    session->token);
        constexpr size_t kRecentHellos = 256;
        if (recent_hello_randoms_.size() < kRecentHellos) {
          recent_hello_randoms_.push_back(*random);
        } else {
          recent_hello_randoms_[next_hello_random_] = *random;
          next_hello_random_ = (next_hello_random_ + 1) % kRecentHellos;
        }
      }
      if (config_.predict || config_.adaptive_fov.enabled) session->predictor = PosePredictor(config_.predictor);
      if (config_.adaptive_fov.enabled) session->fov_margin = FovMarginTracker(config_.adaptive_fov);
      session->rate = SendRateController(config_.rate_control);
      session->last_receive_ns = now;
      session->last_heartbeat_sent_ns = now;
      session->datagrams_received = 1;
      sessions_.emplace(session->token, session);
      ++stats_.sessions_opened;
      send_message(session.get(), session->token, session->welcome, from);
      opened = session->info();
    }
  }
  notify(closed, opened ? &*opened : nullptr);
}

}  // namespace dhr::server
