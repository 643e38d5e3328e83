#include "eval_session.hpp"

#include "visibility_error.hpp"

#include "plan/shipped_defaults.hpp"
#include "session/shipped_defaults.hpp"
#include "image/png_writer.hpp"

#include <filesystem>

#include "metrics/image_flip.hpp"
#include "log/log.hpp"
#include "protocol/protocol.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <variant>

namespace dhr::eval {
namespace {

// The simulated client's address as the service sees it (the links carry no addresses of their own).
const net::PeerAddress kClientAddress = net::PeerAddress::ipv4({10, 0, 0, 2}, 5000);
// The connection phase gives up after this much virtual time (the client itself gives up after 5 s).
constexpr int64_t kConnectLimitNs = 10 * net::kNsPerSecond;

net::ImpairmentParams link_params(const Setting& setting, const RunOptions& options, uint64_t seed) {
  net::ImpairmentParams p;
  p.delay_ms = setting.rtt_ms / 2.0;
  p.jitter_ms = options.jitter_ms;
  p.loss = options.loss;
  p.seed = seed;
  return p;
}

// Half the frame's modelled compute time per traced eye (the service traces both eyes of a frame).
int64_t server_ns_per_eye(const RunOptions& options) {
  return static_cast<int64_t>(std::llround(options.server_ms * 1e6 / 2.0));
}

server::ServiceConfig service_config(const Setting& setting, const RunOptions& options, const SessionShared& shared) {
  server::ServiceConfig c;
  // The default method runs what dhr-server --reuse auto does.
  c.reuse = setting.method.shipped &&
            server::shipped::reuse_by_default(shared.tracer->backend() == server::TracerBackend::kEmbree,
                                              c.soft_levels, shared.soft_lights != 0);
  c.token_seed = options.seed * 2 + 1;  // never 0 (0 would draw tokens from std::random_device)
  c.predict = server_predicts(setting.method);
  c.adaptive_fov.enabled = server_adapts_fov(setting.method);
  c.predict_horizon_ns = -1;  // automatic: the session's measured RTT + queueing + the last trace time
  c.codec_v2 = options.codec_v2;
  c.predictor.velocity_window_ns = static_cast<int64_t>(std::llround(options.predict_window_ms * 1e6));
  c.predictor.max_horizon_ns = static_cast<int64_t>(std::llround(options.predict_max_horizon_ms * 1e6));
  c.predictor.soft_horizon_ns = static_cast<int64_t>(std::llround(options.predict_soft_horizon_ms * 1e6));
  c.predictor.damping_tau_ns = static_cast<int64_t>(std::llround(options.predict_damping_ms * 1e6));
  c.predictor.quadratic_window_ns = static_cast<int64_t>(std::llround(options.predict_quadratic_ms * 1e6));
  return c;
}

client::VisibilityClientConfig client_config(const Setting& setting, const RunOptions& options,
                                             const SessionShared& shared) {
  client::VisibilityClientConfig c;
  c.format = TracedFormat{shared.eye, setting.guard_band};
  c.codec_v2 = options.codec_v2;
  c.soft_lights = shared.soft_lights;
  c.light_slots = shared.light_slots;
  c.max_frames_in_flight = 8;
  c.nonce_seed = options.seed;
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

// The client's frame policy for the setting's method: stale shows the bits unwarped, paper warps with x_max
// (all: the newest pose, the client's default schedule); paper+pred differs on the server only.
client::PlannerSettings planner_settings(const Setting& setting, const SessionShared& shared) {
  client::PlannerSettings s;
  if (setting.method.shipped) {  // dhr-xrclient's own schedule
    s.schedule = client::shipped::kSchedule;
    s.x_max = client::shipped::kXMax;
  } else if (setting.method.method == Method::kStale) {
    s.schedule = client::Schedule::kStale;
  } else if (setting.x_max < 0) {
    s.schedule = client::Schedule::kNewest;
  } else {
    s.schedule = client::Schedule::kPaper;
    s.x_max = static_cast<uint64_t>(setting.x_max);
  }
  s.history_frames = std::max<size_t>(shared.frames_total, 1);  // every frame of the run stays known
  return s;
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

int64_t ServerClock::take_busy_ns() {
  const int64_t busy = busy_ns_;
  busy_ns_ = 0;
  return busy;
}

void ModelledTimeTracer::traced(const server::TraceStats& stats) {
  sums_.add_counts(stats);
  clock_.add_busy_ns(ns_per_eye_);
}

void ModelledTimeTracer::trace(const Camera& camera, VisibilityBuffer& out, server::TraceStats& out_stats) {
  inner_.trace(camera, out, out_stats);
  traced(out_stats);
}

void ModelledTimeTracer::trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out,
                                      server::TraceStats& out_stats) {
  inner_.trace_lights(camera, lights, out, out_stats);
  traced(out_stats);
}

void ModelledTimeTracer::trace_layout(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out,
                                      server::TraceStats& out_stats) {
  inner_.trace_layout(camera, layout, out, out_stats);
  traced(out_stats);
}

void ModelledTimeTracer::trace_reusing(const Camera& camera, const VisibilityLayout& layout,
                                       const server::ReuseRequest& request, VisibilityBuffer& out,
                                       server::TraceStats& out_stats) {
  inner_.trace_reusing(camera, layout, request, out, out_stats);
  traced(out_stats);
}

bool CountingSender::send_to(std::span<const uint8_t> datagram, const net::PeerAddress& to) {
  DatagramHeader header;
  const bool shard = decode_header(datagram, header) == DecodeError::kNone && header.type == MessageType::kVisibilityShard;
  if (!link_.send_to(datagram, to)) return false;
  if (shard) shard_bytes_ += datagram.size();
  return true;
}

SettingSession::SettingSession(const Setting& setting, const RunOptions& options, const SessionShared& shared,
                               uint32_t index)
    : setting_(setting), shared_(shared), format_{shared.eye, setting.guard_band}, clock_(0), server_clock_(clock_),
      uplink_(link_params(setting, options, options.seed * 2 + 0), clock_),
      downlink_(link_params(setting, options, options.seed * 2 + 1), server_clock_), server_out_(downlink_),
      tracer_(*shared.tracer, server_clock_, server_ns_per_eye(options)) {
  totals_.bit_error_per_light.assign(shared.light_count, 0.0);
  totals_.visibility_error_per_light.assign(shared.light_count, 0.0);
  cap_ms_ = options.predict_max_horizon_ms;
  warp_ = warp_settings(for_scene(setting.method, shared.soft_lights != 0), options);
  renderer_ = shared.renderer;
  if (warp_.depth_test && warp_.depth_splat) {
    if (shared.scene == nullptr) throw std::invalid_argument("SettingSession: a depth-splat setting needs the scene");
    own_renderer_ = std::make_unique<EyeRenderer>(shared.renderer->context(), *shared.scene, shared.eye,
                                                  shared.shadow_maps, shared.forward);
    renderer_ = own_renderer_.get();
  }
  snapshot_dir_ = options.out_dir;
  service_ = std::make_unique<server::VisibilityService>(tracer_, service_config(setting, options, shared), server_out_,
                                                         server_clock_);
  client_ = std::make_unique<client::VisibilityClient>(client_config(setting, options, shared), uplink_, clock_);
  source_ = std::make_unique<SessionVisibilitySource>(*client_, uses_server_visibility(setting.method));
  client::CoordinatorOptions frame_options;
  frame_options.plan = planner_settings(setting, shared);
  frame_options.upload_keys = false;  // the eye pipelines may be shared with the other settings
  frame_options.shadow_owner = index + 1;
  frame_options.gpu_wait_timeout_ns = std::numeric_limits<uint64_t>::max();  // however long a slow device takes
  frames_ = std::make_unique<client::FrameCoordinator>(renderer_->context(), renderer_->pipeline(),
                                                       *source_, frame_options);
  frames_->set_on_frame([this](const client::FrameRecord& record) { last_record_ = record; });
  connect();
}

SettingSession::~SettingSession() = default;

// The connection phase, before the trace plays: Hello -> Welcome, then heartbeats until the service has
// an echo of its own heartbeat (its RTT sample, which the automatic prediction horizon needs).
void SettingSession::connect() {
  const int64_t period = client::kVirtualFramePeriodNs;
  bool echo_pending = false;
  uint64_t heartbeats_before_echo = 0;
  int64_t t = 0;
  bool done = false;
  for (; t <= kConnectLimitNs && !done; t += period) {
    run_until(t, false);
    clock_.set_ns(std::max(clock_.now_ns(), t));
    client_->tick();
    service_->tick();
    run_until(t, true);
    if (client_->failed()) throw std::runtime_error("setting " + setting_label(setting_) + ": " + client_->failure());
    const client::ClientNetStats stats = client_->stats();
    if (!echo_pending && stats.heartbeats_received > 0) {
      echo_pending = true;  // the client's next heartbeat echoes the service's
      heartbeats_before_echo = stats.heartbeats_sent;
    } else if (echo_pending && stats.heartbeats_sent > heartbeats_before_echo && uplink_.in_flight() == 0) {
      done = true;
    }
  }
  if (!client_->connected()) {
    throw std::runtime_error("setting " + setting_label(setting_) + ": the client did not connect");
  }
  if (!done) log::warn("dhr-eval: %s: no heartbeat round trip before the trace starts", setting_label(setting_).c_str());
  const std::optional<Welcome> welcome = client_->welcome();
  if (!welcome || welcome->format() != format_) {
    throw std::runtime_error("setting " + setting_label(setting_) + ": the server granted another guard band");
  }
  totals_.connect_ms = static_cast<double>(t) * 1e-6;
  time_offset_ns_ = t + period;
}

// Discrete events in time order: datagrams reaching the service, the service's worker tracing, datagrams
// reaching the client. At equal times the service receives first, then traces, then the client receives.
void SettingSession::run_until(int64_t t_ns, bool inclusive) {
  std::optional<int64_t> work_at;  // when the worker takes the pending pose: on arrival, or when it is free
  for (;;) {
    const auto due = [&](const std::optional<int64_t>& at) { return at && (inclusive ? *at <= t_ns : *at < t_ns); };
    const std::optional<int64_t> up = uplink_.next_delivery_ns(), down = downlink_.next_delivery_ns();
    if (server_work_ && !work_at) work_at = std::max(server_free_ns_, clock_.now_ns());
    int which = -1;
    int64_t at = 0;
    for (const auto& [candidate, id] : {std::pair{up, 0}, std::pair{work_at, 1}, std::pair{down, 2}}) {
      if (due(candidate) && (which < 0 || *candidate < at)) {
        which = id;
        at = *candidate;
      }
    }
    if (which < 0) break;
    clock_.set_ns(std::max(clock_.now_ns(), at));
    if (which == 0) {
      uplink_.deliver_until(at, [this](const net::SimulatedDelivery& d) { service_->on_datagram(d.bytes, kClientAddress); });
      server_work_ = true;
    } else if (which == 1) {
      work_at.reset();
      process_on_server(at);
    } else {
      downlink_.deliver_until(at, [this](const net::SimulatedDelivery& d) { deliver_to_client(d); });
    }
  }
  clock_.set_ns(std::max(clock_.now_ns(), t_ns));
}

void SettingSession::process_on_server(int64_t t_ns) {
  server_work_ = false;
  const bool predict = server_predicts(setting_.method);
  const server::ServiceStats before = predict ? service_->stats() : server::ServiceStats{};
  service_->process_pending();
  server_free_ns_ = t_ns + server_clock_.take_busy_ns();
  if (!predict) return;
  // The service counts sums only; one call traces at most this one session's frame, so the differences
  // are that frame's horizon and fallback.
  const server::ServiceStats after = service_->stats();
  if (after.frames_predicted == before.frames_predicted) return;
  const double horizon_ms = after.prediction_horizon_ms - before.prediction_horizon_ms;
  const double cap_ms = cap_ms_;
  if (after.prediction_fallbacks == before.prediction_fallbacks && horizon_ms >= cap_ms - 1e-6) {
    totals_.prediction_capped += 1;
  }
}

void SettingSession::deliver_to_client(const net::SimulatedDelivery& delivery) {
  const auto start = std::chrono::steady_clock::now();
  client_->on_datagram(delivery.bytes);
  totals_.decode_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void SettingSession::advance(const FramePose& sample) {
  frame_ = sample.frame;
  frames_->record_pose(sample);
  const int64_t t = display_ns(sample);
  run_until(t, false);
  client_->tick();
  service_->tick();
  // Display time on the setting's clock. local asks the server for nothing (it stays connected, idle).
  if (uses_server_visibility(setting_.method))
    client_->send_pose(FramePose{sample.frame, t, sample.views, sample.scene_time_ns});
  run_until(t, true);
}

void SettingSession::measure(const Truth& truth) {
  const FramePose& now = shared_.history->at(frame_);
  renderer_->pipeline().set_warp_settings(warp_);
  const auto start = std::chrono::steady_clock::now();
  if (!frames_->run_frame(client::FrameInput{now, false}, sink_) || !frames_->finish()) {
    throw std::runtime_error("setting " + setting_label(setting_) + ": " + frames_->last_error());
  }
  const double host_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / 2.0;
  const bool server = uses_server_visibility(setting_.method);
  for (uint32_t eye = 0; eye < 2; ++eye) {
    const client::EyeFrameRecord& p = last_record_.eyes[eye];
    if (!p.has_visibility || !server) totals_.eye_frames_without_data += 1;
    if (p.first_use && server) {
      totals_.responses += 1;
      totals_.response_ms += static_cast<double>(p.visibility_age_ns.value_or(0)) * 1e-6;
    }
    EyeRender rendered = renderer_->read_back(eye);
    rendered.stats = p.stats;
    rendered.host_ms = host_ms;
    if (snapshot_frame_ && frame_ == *snapshot_frame_) write_snapshot(rendered, truth, static_cast<int>(eye));
    add_image_errors(rendered, truth, static_cast<int>(eye));
    totals_.filled_other_eye += static_cast<double>(rendered.stats.warp.filled_other_eye) / pixels_per_eye();
    totals_.filled_shadow_map += static_cast<double>(rendered.stats.warp.filled_shadow_map) / pixels_per_eye();
    totals_.filled_older += static_cast<double>(rendered.stats.warp.filled_older) / pixels_per_eye();
    totals_.filled_neighbour += static_cast<double>(rendered.stats.warp.filled_neighbour) / pixels_per_eye();
    totals_.edges_shadow_map += static_cast<double>(rendered.stats.warp.edges_shadow_map) / pixels_per_eye();
    totals_.shadow_overrides += static_cast<double>(rendered.stats.warp.shadow_overrides) / pixels_per_eye();
    totals_.motion_unknown += static_cast<double>(rendered.stats.warp.motion_unknown) / pixels_per_eye();
    totals_.unfilled += static_cast<double>(rendered.stats.warp.unfilled()) / pixels_per_eye();
    totals_.disoccluded +=
        static_cast<double>(rendered.stats.warp[render::WarpStatus::kDisoccluded]) / pixels_per_eye();
    totals_.traced_depth_ms += rendered.stats.gpu.traced_depth_ms;
    totals_.warp_ms += rendered.stats.gpu.warp_ms;
    const double pixels = static_cast<double>(shared_.eye.width) * shared_.eye.height;
    totals_.unknown_frac += static_cast<double>(rendered.stats.unknown_pixels()) / pixels;
    totals_.client_ms += rendered.stats.gpu.valid ? rendered.stats.gpu.total_ms : rendered.host_ms;
    totals_.client_gpu_timed += rendered.stats.gpu.valid ? 1 : 0;
    totals_.client_forward += rendered.stats.forward ? 1 : 0;
    totals_.frames_behind += static_cast<double>(p.age);
    totals_.frames_predicted += static_cast<double>(p.predicted);
  }
}

void SettingSession::write_snapshot(const EyeRender& rendered, const Truth& truth, int eye) const {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(snapshot_dir_) / "snapshots";
  fs::create_directories(dir);
  char rtt[32];
  std::snprintf(rtt, sizeof rtt, "%g", setting_.rtt_ms);
  const std::string suffix = "_eye" + std::to_string(eye) + ".png";
  const std::string base = method_name(setting_.method) + "_rtt" + rtt + "_guard" + setting_.guard;
  const Extent e = shared_.eye;
  auto write = [&](const fs::path& path, uint32_t channels, const std::vector<uint8_t>& pixels) {
    if (auto err = write_png(path.string(), e.width, e.height, channels, pixels)) {
      std::fprintf(stderr, "dhr-eval: %s\n", err->c_str());
    }
  };
  write(dir / (base + suffix), 4, rendered.rgba);
  write(dir / ("exact_guard" + setting_.guard + suffix), 4, truth.rgba[eye]);
  // Wrong visibility bits: red where lit but shadowed in the truth, green where shadowed but lit.
  std::vector<uint8_t> diff(size_t{e.width} * e.height * 3, 0);
  for (size_t i = 0; i < diff.size() / 3; ++i) {
    const uint32_t got = rendered.mask.mask_at(i), want = truth.mask[eye].mask_at(i);
    diff[i * 3 + 0] = (got & ~want) != 0 ? 255 : 0;
    diff[i * 3 + 1] = (want & ~got) != 0 ? 255 : 0;
    diff[i * 3 + 2] = want != 0 ? 48 : 0;
  }
  write(dir / (base + "_wrong_bits" + suffix), 3, diff);
}

void SettingSession::add_image_errors(const EyeRender& rendered, const Truth& truth, int eye) {
  const LumaImage luma = luma_from_rgba8(rendered.rgba, shared_.eye.width, shared_.eye.height);
  const std::optional<BitError> bits = visibility_bit_error(rendered.mask, truth.mask[eye]);
  const std::optional<double> s = ssim(luma, truth.luma[eye]);
  totals_.eye_frames += 1;
  if (bits) {
    totals_.bit_error += bits->fraction();
    for (uint32_t l = 0; l < shared_.light_count; ++l) totals_.bit_error_per_light[l] += bits->light_fraction(l);
  }
  const std::optional<VisibilityError> k =
      visibility_error(rendered.mask, renderer_->layout(), truth.exact[eye], rendered.soft);
  totals_.display_pixels += rendered.mask.pixel_count();
  if (k) {
    totals_.surface_pixels += k->surface_pixels;
    for (uint32_t l = 0; l < shared_.light_count; ++l) totals_.visibility_error_per_light[l] += k->per_light[l];
  }
  totals_.ssim += s.value_or(0.0);
  double mse = 0.0;
  for (size_t i = 0; i < luma.pixels.size(); ++i) {
    const double d = luma.pixels[i] - truth.luma[eye].pixels[i];
    mse += d * d;
  }
  totals_.mse += luma.pixels.empty() ? 0.0 : mse / static_cast<double>(luma.pixels.size());
  const std::optional<FlipResult> flip = flip_ldr(truth.rgba[eye], rendered.rgba, shared_.eye.width, shared_.eye.height);
  if (flip) {
    totals_.flip += flip->mean;
    totals_.flip_frames += 1;
  }
}

SettingTotals SettingSession::totals() const {
  SettingTotals t = totals_;
  const server::ServiceStats s = service_->stats();
  t.traces = s.frames_traced * 2;
  t.trace_stats = tracer_.sums();
  t.server_ms = s.trace_ms;
  t.encode_ms = s.encode_ms;
  t.bytes_down = server_out_.shard_bytes();
  t.predictions = s.frames_predicted;
  t.prediction_fallbacks = s.prediction_fallbacks;
  t.horizon_ms = s.prediction_horizon_ms;
  t.eyes_fov_widened = s.eyes_fov_widened;
  t.fov_span_ratio = s.fov_span_ratio;
  t.poses_skipped_identical = s.poses_skipped_identical;
  t.poses_superseded = s.poses_superseded;
  t.datagrams_lost = uplink_.stats().model.lost + downlink_.stats().model.lost;
  return t;
}

}  // namespace dhr::eval
