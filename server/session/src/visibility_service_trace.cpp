// VisibilityService: tracing pending poses (optionally predicted), encoding and sending the shards.
#include "session/service_session.hpp"

#include "log/log.hpp"

#include <limits>
#include <mutex>

namespace dhr::server {

using namespace session_detail;

namespace {

// The scene time `horizon_ns` after `scene_time_ns` (saturating: both come from the wire or the clock).
int64_t scene_time_after(int64_t scene_time_ns, int64_t horizon_ns) {
  const int64_t h = std::max<int64_t>(horizon_ns, 0);
  return scene_time_ns > std::numeric_limits<int64_t>::max() - h ? std::numeric_limits<int64_t>::max()
                                                                  : scene_time_ns + h;
}

}  // namespace

// Claims the next session to trace (under mutex_): due, pending, not being traced by another worker, and the
// one traced least recently (never traced first), so sessions take turns whoever sends faster. A pose
// identical to the last one traced (both views, and in a moving scene the scene time) is skipped (counted) and
// the search goes on. Marks the session busy. The frame's scene time is the pose's, plus the horizon when
// predicting: the scene as it will be at the display the views are predicted for.
std::optional<VisibilityService::Work> VisibilityService::claim_work() {
  const int64_t now = clock_.now_ns();
  for (;;) {
    std::shared_ptr<Session> next;
    for (auto& [token, s] : sessions_) {
      if (!s->pending || s->busy || !s->rate.due(now, s->last_trace_ns)) continue;  // capped: the pose waits
      if (!next || s->last_trace_ns < next->last_trace_ns) next = s;
    }
    if (!next) return std::nullopt;
    Session* s = next.get();
    PoseUpdate pose = *s->pending;
    s->pending.reset();
    const bool identical = s->have_traced && same_view(pose.views[0], s->traced_views[0]) &&
                           same_view(pose.views[1], s->traced_views[1]) &&
                           (!scene_moves_ || (pose.scene_time_ns == s->traced_scene_time_ns &&
                                              s->overrides.revision() == s->traced_overrides_revision));
    const bool refresh_due = config_.identical_refresh_ns > 0 && now - s->last_trace_ns >= config_.identical_refresh_ns;
    if (config_.skip_identical_pose && identical && !refresh_due) {
      ++stats_.poses_skipped_identical;
      ++s->frames_dropped;
      continue;
    }
    s->have_traced = true;
    s->traced_views = pose.views;
    s->traced_scene_time_ns = pose.scene_time_ns;
    s->traced_overrides_revision = s->overrides.revision();
    s->last_trace_ns = now;
    s->busy = true;
    Work w{next, pose, s->overrides, {s->codec[0].acked, s->codec[1].acked}, s->rate.pacing_dps().has_value(),
           s->pending_receive_ns};
    if (config_.predict || config_.adaptive_fov.enabled) {
      int64_t horizon = config_.predict_horizon_ns;
      if (horizon < 0) {
        horizon = s->offset.rtt_ns() + (now - s->pending_receive_ns) + s->last_process_ns;
        if (config_.horizon_on_frame_grid) horizon = round_up_to_frame_grid(horizon, s->predictor.frame_period_ns());
      }
      if (config_.predict) {
        const PredictedViews predicted = s->predictor.predict(pose.display_time_ns + horizon);
        w.traced.views = predicted.views;
        w.traced.scene_time_ns = scene_time_after(pose.scene_time_ns, horizon);
        ++stats_.frames_predicted;
        if (predicted.fell_back) ++stats_.prediction_fallbacks;
        stats_.prediction_horizon_ms += static_cast<double>(predicted.horizon_ns) / 1e6;
      }
      if (config_.adaptive_fov.enabled) widen_fov(*s, pose.display_time_ns + horizon, w.traced.views);
    }
    return w;
  }
}

size_t VisibilityService::process_pending() {
  size_t traced = 0;
  for (;;) {
    std::optional<Work> work;
    {
      std::lock_guard lock(mutex_);
      work = claim_work();
    }
    if (!work) return traced;
    try {
      traced += trace_and_send(*work) ? 1 : 0;
    } catch (const std::exception& e) {  // bad_alloc: the frame is lost, the service goes on
      log::error("session %016llx: %s", static_cast<unsigned long long>(work->session->token), e.what());
      std::lock_guard lock(mutex_);
      ++stats_.trace_errors;
    }
    {
      std::lock_guard lock(mutex_);
      work->session->busy = false;
    }
    work_ready_.notify_one();  // a pose for it may have arrived meanwhile
  }
}

// Adaptive FOV: remembers the views traced for the target time (measured when the client's pose for it
// arrives), then widens each eye by the recent shortfall. Under mutex_.
void VisibilityService::widen_fov(Session& s, int64_t target_time_ns, std::array<View, 2>& views) {
  s.fov_margin.traced(target_time_ns, views);
  const TracedFormat format = s.welcome.format();
  for (size_t e = 0; e < 2; ++e) {
    const View widened = s.fov_margin.widen(views[e], e, format);
    const Tangents a = Tangents::from_fov(views[e].fov), b = Tangents::from_fov(widened.fov);
    const double ratio = (b.width() * b.height()) / (a.width() * a.height());
    if (ratio != 1.0) ++stats_.eyes_fov_widened;
    stats_.fov_span_ratio += ratio;
    views[e] = widened;
  }
}

// Codec v2 for one eye: against the frame the client acknowledged, if this eye's ring of sent frames still has
// it (then fewer than kV2ReferenceFrames newer frames were sent, so the client still holds it), unless an intra
// refresh is due; then remembers the traced buffer as a future reference. By the worker that claimed the session.
std::vector<VisibilityShard> VisibilityService::encode_v2(Session& s, Eye eye, const Work& work, const Camera& camera,
                                                         const VisibilityBuffer& traced, uint64_t& inter_eyes,
                                                         uint64_t& intra_eyes) {
  Session::EyeCodec& ec = s.codec[static_cast<size_t>(eye)];
  if (ec.sent.empty()) ec.sent.resize(kV2ReferenceFrames);
  const int64_t now = clock_.now_ns();
  const bool refresh_due = !ec.had_intra || now - ec.last_intra_ns >= config_.v2_intra_refresh_ns;
  const std::optional<uint64_t> acked = work.acked[static_cast<size_t>(eye)];
  const Session::SentFrame* ref = nullptr;
  if (!refresh_due && acked && *acked < work.traced.frame && work.traced.frame - *acked <= 65535) {
    for (const Session::SentFrame& f : ec.sent)
      if (!f.buffer.data.empty() && f.frame == *acked) ref = &f;
  }
  const V2Reference reference{ref ? &ref->buffer : nullptr, ref ? ref->frame : 0, &camera, ref ? &ref->camera : nullptr};
  std::vector<EncodedShard> encoded;
  if (!encode_visibility_v2(traced, work.traced.frame, ref ? &reference : nullptr, config_.encode, encoded)) return {};
  if (ref) {
    ++inter_eyes;
  } else {
    ++intra_eyes;
    ec.had_intra = true;
    ec.last_intra_ns = now;
  }
  Session::SentFrame& slot = ec.sent[ec.next];
  slot.frame = work.traced.frame;
  slot.buffer = traced;  // recycled storage after the ring's first round
  slot.camera = camera;
  ec.next = (ec.next + 1) % ec.sent.size();
  return shards_as_messages(traced, work.traced.frame, eye, work.traced.views[static_cast<size_t>(eye)], encoded);
}

void VisibilityService::trace_reusing(Session& s, size_t eye, const Camera& camera, VisibilityBuffer& out,
                                      TraceStats& stats) {
  std::shared_ptr<ReuseFrame>& writing = s.reuse_writing[eye];
  if (!writing || writing.use_count() > 1) writing = std::make_shared<ReuseFrame>();  // a reader holds the old one
  // The sources, held for the trace: this eye's previous trace, this frame's left eye (for the right), then the
  // newest traces of the same eye of up to kReuseSharedSessions other sessions (the scene's view-independent state).
  std::vector<std::shared_ptr<ReuseFrame>> held;
  ReuseRequest request;
  {
    std::lock_guard lock(mutex_);
    request.previous = s.reuse_newest[eye].get();
    if (s.reuse_newest[eye]) held.push_back(s.reuse_newest[eye]);
    if (eye == 1 && s.reuse_newest[0]) held.push_back(s.reuse_newest[0]);
    size_t others = 0;
    for (const auto& [token, other] : sessions_) {
      if (other.get() == &s || !other->reuse_newest[eye] || others == kReuseSharedSessions) continue;
      held.push_back(other->reuse_newest[eye]);
      ++others;
    }
  }
  for (const auto& f : held)
    if (f.get() != request.previous) request.shared.push_back(f.get());
  request.record = writing.get();
  tracer_.trace_reusing(camera, s.layout, request, out, stats);
  held.clear();
  std::lock_guard lock(mutex_);
  // The old newest is the next one written, unless a reader still holds it then (a new one is made).
  std::swap(s.reuse_newest[eye], writing);
}

bool VisibilityService::trace_and_send(const Work& work) {
  Session& s = *work.session;
  const TracedFormat format = s.welcome.format();
  double trace_ms = 0.0, trace_gpu_ms = 0.0, encode_ms = 0.0, update_ms = 0.0;
  uint64_t shards = 0, inter_eyes = 0, intra_eyes = 0, shed = 0, rays = 0;
  uint64_t soft_pairs = 0, soft_contributing = 0, soft_refined = 0, soft_rays = 0, reused_pixels = 0, reused_pairs = 0;
  std::array<double, 2> eye_trace_ms{};
  bool ok = true, at_scene_time = false;
  const int64_t start_ns = clock_.now_ns();
  // Each worker thread its own scratch (the session's requested lights only): no allocation in steady state.
  thread_local VisibilityBuffer scratch;
  // A moving scene: the tracer is moved to the frame's scene time and both eyes are traced there, under one lock
  // (set_scene_time is not concurrent with tracing). The left eye is still sent before the right one is traced.
  std::unique_lock<std::mutex> tracer_lock;
  for (int e = 0; e < 2 && ok; ++e) {
    // Traced for the view the client will decode from the shards, which carry `view`: with a predicted view
    // (f64 orientation) that is not `view` itself, and the client would check bits against another camera.
    const View& view = work.traced.views[e];
    const std::optional<View> decoded = view_as_decoded(view);
    if (!decoded) {
      log::warn("session %016llx frame %llu: no client would accept the view to trace (predicted out of range)",
                static_cast<unsigned long long>(s.token), static_cast<unsigned long long>(work.traced.frame));
      ok = false;
      break;
    }
    const Camera camera = format.camera(*decoded);
    TraceStats trace_stats;
    try {
      if (scene_moves_ && e == 0) {
        tracer_lock = std::unique_lock(tracer_mutex_);
        // App-moved nodes where the session's transforms put them then (extrapolated beyond the newest).
        tracer_.set_scene_time(node_stamp_seconds(work.traced.scene_time_ns),
                               work.overrides.empty() ? nullptr : &work.overrides);
        update_ms = tracer_.last_motion_update_ms();
        at_scene_time = true;
      }
      // Only the lights the client asked for (the layout's, the first light_count): the others cost no ray.
      if (config_.reuse) {
        trace_reusing(s, static_cast<size_t>(e), camera, scratch, trace_stats);
      } else {
        tracer_.trace_layout(camera, s.layout, scratch, trace_stats);
      }
    } catch (const std::exception& ex) {
      log::warn("session %016llx frame %llu: trace failed: %s", static_cast<unsigned long long>(s.token),
                static_cast<unsigned long long>(work.traced.frame), ex.what());
      ok = false;
      break;
    }
    if (e == 1 && tracer_lock.owns_lock()) tracer_lock.unlock();  // both eyes traced at the frame's scene time
    trace_ms += trace_stats.trace_ms;
    trace_gpu_ms += trace_stats.gpu_ms;
    eye_trace_ms[static_cast<size_t>(e)] = trace_stats.trace_ms;
    rays += trace_stats.primary_rays + trace_stats.shadow_rays;
    reused_pixels += trace_stats.reused_pixels;
    reused_pairs += trace_stats.reused_pairs;
    soft_pairs += trace_stats.soft_pairs;
    soft_contributing += trace_stats.soft_contributing_pairs;
    soft_refined += trace_stats.soft_refined_pairs;
    soft_rays += trace_stats.soft_shadow_rays;
    const int64_t encode_start = net::steady_now_ns();
    std::vector<VisibilityShard> encoded =
        (s.welcome.capabilities & kCapabilityCodecV2)
            ? encode_v2(s, static_cast<Eye>(e), work, camera, scratch, inter_eyes, intra_eyes)
            : make_visibility_shards(scratch, work.traced.frame, static_cast<Eye>(e), view, config_.encode);
    if (encoded.empty()) {
      ok = false;
      break;
    }
    for (VisibilityShard& shard : encoded) shard.scene_time_ns = work.traced.scene_time_ns;
    if (!s.open.load(std::memory_order_acquire)) return false;  // closed while tracing: nothing to send
    if (work.paced) {  // into the pacing queue; what is left of an older frame is shed
      std::lock_guard pace_lock(s.pace_mutex);
      if (e == 0 && !s.paced.empty()) {
        shed += s.paced.size();
        s.paced.clear();
      }
      for (const VisibilityShard& shard : encoded)
        if (send_message(&s, s.token, shard, s.peer, {}, Envelope::kAuto, &s.paced) > 0) ++shards;
    } else {
      for (const VisibilityShard& shard : encoded)
        if (send_message(&s, s.token, shard, s.peer) > 0) ++shards;
    }
    encode_ms += elapsed_ms(encode_start);
  }
  if (tracer_lock.owns_lock()) tracer_lock.unlock();  // a failed frame: before the service's lock below
  shards_sent_.fetch_add(shards, std::memory_order_relaxed);
  std::lock_guard lock(mutex_);
  stats_.trace_ms += trace_ms;
  stats_.trace_gpu_ms += trace_gpu_ms;
  stats_.encode_ms += encode_ms;
  stats_.eyes_coded_v2_inter += inter_eyes;
  stats_.eyes_coded_v2_intra += intra_eyes;
  stats_.datagrams_shed += shed;
  stats_.rays += rays;
  stats_.reused_pixels += reused_pixels;
  stats_.reused_pairs += reused_pairs;
  stats_.soft_pairs += soft_pairs;
  stats_.soft_contributing_pairs += soft_contributing;
  stats_.soft_refined_pairs += soft_refined;
  stats_.soft_shadow_rays += soft_rays;
  if (!ok) {
    ++stats_.trace_errors;
    return false;
  }
  ++stats_.frames_traced;
  if (at_scene_time) {  // both for frames sent only: their mean is the update cost per traced frame
    ++stats_.frames_at_scene_time;
    stats_.scene_update_ms += update_ms;
  }
  for (const double ms : eye_trace_ms) stats_.trace_hist.add(ms);
  stats_.response_hist.add(static_cast<double>(std::max<int64_t>(clock_.now_ns() - work.received_ns, 0)) * 1e-6);
  s.last_process_ns = std::max<int64_t>(clock_.now_ns() - start_ns, 0);
  s.frames_done.fetch_add(1, std::memory_order_relaxed);
  s.newest_frame_traced = std::max(s.newest_frame_traced, work.traced.frame);
  return true;
}

}  // namespace dhr::server
