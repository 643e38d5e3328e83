#include "eval_session.hpp"

#include "core/codec.hpp"
#include "core/log.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <variant>

namespace dhr::eval {
namespace {

constexpr uint64_t kSessionToken = 0xD4E7A1;

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

net::ImpairmentParams link_params(const Setting& setting, const RunOptions& options, uint64_t seed) {
  net::ImpairmentParams p;
  p.delay_ms = setting.rtt_ms / 2.0;
  p.jitter_ms = options.jitter_ms;
  p.loss = options.loss;
  p.seed = seed;
  return p;
}

ReassemblerConfig reassembler_config(const Setting& setting, const SessionShared& shared) {
  ReassemblerConfig c;
  c.width = shared.eye.width + setting.guard_px.x;
  c.height = shared.eye.height + setting.guard_px.y;
  c.light_count = shared.light_count;
  c.max_frames_in_flight = 8;
  return c;
}

std::optional<std::array<View, 2>> decode_pose_views(std::span<const uint8_t> bytes) {
  Datagram datagram;
  if (decode_datagram(bytes.data(), bytes.size(), datagram) != DecodeError::kNone) return std::nullopt;
  const PoseUpdate* update = std::get_if<PoseUpdate>(&datagram.message);
  if (!update) return std::nullopt;
  return update->views;
}

bool same_views(const std::array<View, 2>& a, const std::array<View, 2>& b) {
  for (size_t i = 0; i < 2; ++i) {
    if (a[i].pose.position != b[i].pose.position || a[i].pose.orientation != b[i].pose.orientation ||
        a[i].fov.angle_left != b[i].fov.angle_left || a[i].fov.angle_right != b[i].fov.angle_right ||
        a[i].fov.angle_up != b[i].fov.angle_up || a[i].fov.angle_down != b[i].fov.angle_down) {
      return false;
    }
  }
  return true;
}

}  // namespace

std::array<View, 2> wire_views(const std::array<View, 2>& views) {
  std::array<View, 2> current = views;
  for (int i = 0; i < 4; ++i) {
    Datagram datagram{1, 0, PoseUpdate{0, 0, current}};
    const std::optional<std::array<View, 2>> decoded = decode_pose_views(encode_datagram(datagram));
    if (!decoded) return current;  // not encodable: leave as is (the caller's poses are validated)
    if (same_views(*decoded, current)) break;
    current = *decoded;
  }
  return current;
}

SettingSession::SettingSession(const Setting& setting, const RunOptions& options, const SessionShared& shared)
    : setting_(setting), shared_(shared), clock_(0),
      uplink_(link_params(setting, options, options.seed * 2 + 0), clock_),
      downlink_(link_params(setting, options, options.seed * 2 + 1), clock_),
      reassembler_(reassembler_config(setting, shared)) {
  totals_.bit_error_per_light.assign(shared.light_count, 0.0);
}

void SettingSession::deliver_until(int64_t t_ns, bool inclusive) {
  for (;;) {
    const std::optional<int64_t> up = uplink_.next_delivery_ns(), down = downlink_.next_delivery_ns();
    const auto due = [&](const std::optional<int64_t>& at) { return at && (inclusive ? *at <= t_ns : *at < t_ns); };
    // Earliest first; the server's deliveries before the client's at equal times.
    if (due(up) && (!due(down) || *up <= *down)) {
      clock_.set_ns(*up);
      uplink_.deliver_until(*up, [this](const net::SimulatedDelivery& d) { on_pose(d); });
    } else if (due(down)) {
      clock_.set_ns(*down);
      downlink_.deliver_until(*down, [this](const net::SimulatedDelivery& d) { on_shard(d); });
    } else {
      break;
    }
  }
  clock_.set_ns(std::max(clock_.now_ns(), t_ns));
}

void SettingSession::advance(const client::PoseSample& sample) {
  frame_ = sample.frame;
  now_ns_ = sample.display_time_ns;
  deliver_until(now_ns_, false);
  clock_.set_ns(now_ns_);
  const std::vector<uint8_t> bytes =
      encode_datagram(Datagram{kSessionToken, up_sequence_++, PoseUpdate{sample.frame, sample.display_time_ns, sample.views}});
  if (!bytes.empty() && uplink_.send(bytes)) {
    totals_.bytes_up += bytes.size();
    totals_.poses_sent += 1;
  }
  reassembler_.set_newest_requested_frame(sample.frame);
  deliver_until(now_ns_, true);
}

// Server side: one PoseUpdate -> (prediction) -> trace both eyes -> encode -> shards on the downlink.
void SettingSession::on_pose(const net::SimulatedDelivery& delivery) {
  Datagram datagram;
  if (decode_datagram(delivery.bytes.data(), delivery.bytes.size(), datagram) != DecodeError::kNone) return;
  const PoseUpdate* update = std::get_if<PoseUpdate>(&datagram.message);
  if (!update) return;
  std::array<View, 2> views = update->views;
  if (setting_.method == Method::kPaperPred) {
    predictor_.add(update->display_time_ns, update->views);
    // The result is shown at the first client frame at or after the pose's display time plus the round
    // trip (the nominal RTT stands in for the server's measured one).
    int64_t period = predictor_.frame_period_ns();
    if (period <= 0) period = client::kVirtualFramePeriodNs;
    const int64_t rtt_ns = static_cast<int64_t>(std::llround(setting_.rtt_ms * 1e6));
    const int64_t frames_ahead = (rtt_ns + period - 1) / period;
    const server::PredictedViews predicted = predictor_.predict(update->display_time_ns + frames_ahead * period);
    totals_.predictions += 1;
    totals_.prediction_fallbacks += predicted.fell_back ? 1 : 0;
    totals_.prediction_capped += predicted.capped ? 1 : 0;
    totals_.horizon_ms += static_cast<double>(predicted.horizon_ns) * 1e-6;
    // No extrapolation (zero horizon, fallback): exactly the received views, as without prediction.
    // Otherwise trace exactly what the shards will carry, so the client warps from exactly what was traced.
    if (!predicted.fell_back && predicted.horizon_ns > 0) views = wire_views(predicted.views);
  }
  for (uint8_t eye = 0; eye < 2; ++eye) {
    const Camera camera = Camera::with_guard_band(views[eye], shared_.eye, setting_.guard_px);
    server::TraceStats stats;
    try {
      shared_.tracer->trace(camera, scratch_, stats);
    } catch (const std::exception& e) {
      log::warn("dhr-eval: frame %llu eye %u not traced: %s", static_cast<unsigned long long>(update->frame_number),
                   static_cast<unsigned>(eye), e.what());
      continue;
    }
    totals_.traces += 1;
    totals_.server_ms += stats.trace_ms;
    const auto start = std::chrono::steady_clock::now();
    const std::vector<VisibilityShard> shards =
        make_visibility_shards(scratch_, update->frame_number, static_cast<Eye>(eye), views[eye]);
    std::vector<std::vector<uint8_t>> datagrams;
    datagrams.reserve(shards.size());
    for (const VisibilityShard& shard : shards) {
      datagrams.push_back(encode_datagram(Datagram{kSessionToken, down_sequence_++, shard}));
    }
    totals_.encode_ms += ms_since(start);
    for (const std::vector<uint8_t>& bytes : datagrams) {
      if (bytes.empty()) continue;
      totals_.bytes_down += bytes.size();
      downlink_.send(bytes);
    }
  }
}

// Client side: one datagram -> reassembler.
void SettingSession::on_shard(const net::SimulatedDelivery& delivery) {
  const auto start = std::chrono::steady_clock::now();
  Datagram datagram;
  if (decode_datagram(delivery.bytes.data(), delivery.bytes.size(), datagram) == DecodeError::kNone) {
    if (const VisibilityShard* shard = std::get_if<VisibilityShard>(&datagram.message)) reassembler_.insert(*shard);
  }
  totals_.decode_ms += ms_since(start);
}

void SettingSession::measure(const Truth& truth) {
  const std::vector<client::PoseSample>& history = *shared_.history;
  const client::PoseSample& now = history.at(frame_);
  for (int eye = 0; eye < 2; ++eye) {
    const ReassembledFrame* received = reassembler_.latest(static_cast<Eye>(eye));
    render::VisibilityInput input;
    View render_view = now.views[eye];
    uint64_t p = 0, x = 0;
    if (received) {
      input.buffer = &received->buffer;
      if (!received->complete()) input.row_valid = received->row_valid;
      p = frame_ - std::min(frame_, received->frame_number);
      if (setting_.method == Method::kStale) {
        // The old bits as if they had been traced for the displayed pose: no reprojection at all.
        input.traced = Camera::with_guard_band(now.views[eye], shared_.eye, setting_.guard_px);
      } else {
        input.traced = Camera::with_guard_band(received->view, shared_.eye, setting_.guard_px);
        x = setting_.x_max < 0 ? p : std::min<uint64_t>(p, static_cast<uint64_t>(setting_.x_max));
        render_view = history.at(frame_ - p + x).views[eye];  // the paper renders frame n with G-buffer n-p+x
      }
      if (!last_used_[eye] || *last_used_[eye] != received->frame_number) {
        last_used_[eye] = received->frame_number;
        totals_.responses += 1;
        totals_.response_ms += static_cast<double>(now.display_time_ns - history.at(received->frame_number).display_time_ns) * 1e-6;
      }
    } else {
      input.traced = Camera::with_guard_band(now.views[eye], shared_.eye, setting_.guard_px);
      totals_.eye_frames_without_data += 1;
    }
    const EyeRender rendered = shared_.renderer->render(eye, render_view, input);
    const LumaImage luma = luma_from_rgba8(rendered.rgba, shared_.eye.width, shared_.eye.height);
    const std::optional<BitError> bits = visibility_bit_error(rendered.mask, truth.mask[eye]);
    const std::optional<double> s = ssim(luma, truth.luma[eye]);
    totals_.eye_frames += 1;
    if (bits) {
      totals_.bit_error += bits->fraction();
      for (uint32_t l = 0; l < shared_.light_count; ++l) totals_.bit_error_per_light[l] += bits->light_fraction(l);
    }
    totals_.ssim += s.value_or(0.0);
    double mse = 0.0;
    for (size_t i = 0; i < luma.pixels.size(); ++i) {
      const double d = luma.pixels[i] - truth.luma[eye].pixels[i];
      mse += d * d;
    }
    totals_.mse += luma.pixels.empty() ? 0.0 : mse / static_cast<double>(luma.pixels.size());
    const double pixels = static_cast<double>(shared_.eye.width) * shared_.eye.height;
    totals_.unknown_frac += static_cast<double>(rendered.stats.unknown_pixels()) / pixels;
    totals_.client_ms += rendered.stats.gpu.valid ? rendered.stats.gpu.total_ms : rendered.host_ms;
    totals_.client_gpu_timed += rendered.stats.gpu.valid ? 1 : 0;
    totals_.frames_behind += static_cast<double>(p);
    totals_.frames_predicted += static_cast<double>(x);
  }
  totals_.datagrams_lost = uplink_.stats().model.lost + downlink_.stats().model.lost;
}

}  // namespace dhr::eval
