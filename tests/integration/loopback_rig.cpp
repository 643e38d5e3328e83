#include "loopback_rig.hpp"

#include "scene/camera_bookmarks.hpp"
#include "scene/scene_hash.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <variant>

namespace dhr::integration {

TracedScene& TracedScene::get() {
  static TracedScene* instance = [] {
    auto* t = new TracedScene();
    SceneLoadResult loaded = load_scene(std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room.gltf");
    if (!loaded) throw std::runtime_error(loaded.error);
    t->scene = std::move(*loaded.scene);
    server::TracerOptions options;
    options.threads = 1;  // the 2-core machine also runs the client and the socket threads
    t->tracer = server::create_tracer(server::TracerBackend::kEmbree, t->scene, options);
    return t;
  }();
  return *instance;
}

LoopbackServer::LoopbackServer(server::VisibilityTracer& tracer, const net::ImpairmentParams& impairment,
                               const std::function<void(server::ServiceConfig&)>& tweak) {
  if (impairment.active()) impaired_ = std::make_unique<net::ImpairedSender>(endpoint_, impairment);
  net::DatagramSender& sender = impaired_ ? static_cast<net::DatagramSender&>(*impaired_) : endpoint_;
  server::ServiceConfig config;
  config.scene_id = "default_room";
  config.scene_hash = scene_content_hash(TracedScene::get().scene);
  config.token_seed = 99;
  if (tweak) tweak(config);
  service_ = std::make_unique<server::VisibilityService>(tracer, config, sender, clock_);
  net::ServerEndpointConfig endpoint_config;
  endpoint_config.bind_address = "127.0.0.1";
  endpoint_config.port = 0;
  endpoint_config.max_datagram_size = kMaxDatagramSize;
  server::VisibilityService* service = service_.get();
  endpoint_.start(endpoint_config,
                  [service](const net::ReceivedDatagram& d) { service->on_datagram(d.bytes, d.from); });
  worker_ = std::thread([this, service] {
    while (!stopping_.load(std::memory_order_acquire)) {
      if (service->wait_for_pending(10 * net::kNsPerMs)) service->process_pending();
      service->tick();
    }
  });
}

LoopbackServer::~LoopbackServer() { stop(); }

void LoopbackServer::stop() {
  stopping_.store(true, std::memory_order_release);
  if (service_) service_->interrupt_wait();
  if (worker_.joinable()) worker_.join();
  if (!endpoint_.running()) return;
  if (impaired_) impaired_->wait_idle(5 * net::kNsPerSecond);
  const uint64_t handed = impaired_ ? impaired_->stats().forwarded : service_->stats().datagrams_sent;
  for (int i = 0; i < 1000; ++i) {  // the socket's I/O thread sends what was queued
    const net::UdpCounters c = endpoint_.counters();
    if (c.datagrams_sent + c.send_errors >= handed) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  endpoint_.stop();
}

std::optional<net::ImpairedSenderStats> LoopbackServer::impairment_stats() const {
  if (!impaired_) return std::nullopt;
  return impaired_->stats();
}

client::VisibilityClientConfig client_config(const EyeSize& size) {
  client::VisibilityClientConfig c;
  c.format = TracedFormat{Extent{size.width, size.height}, GuardBand{size.guard_x, size.guard_y}};
  c.scene_id = "default_room";
  c.nonce_seed = 3;
  return c;
}

std::array<View, 2> views_for_frame(uint64_t frame, const EyeSize& size) {
  CameraBookmark head;
  const double phase = 0.02 * static_cast<double>(frame);
  head.position = {0.4 * std::sin(phase), 1.6 + 0.05 * std::sin(3.0 * phase), 1.35};
  head.target = {-0.1, 0.5, -0.9};
  const Pose T_world_head = look_at_pose(head).value();
  const Fov fov = symmetric_fov(90.0, Extent{size.width, size.height});
  std::array<View, 2> views;
  for (int e = 0; e < 2; ++e) {
    Pose T_head_eye;
    T_head_eye.position = {(e == 0 ? -0.5 : 0.5) * kDefaultIpdMetres, 0.0, 0.0};
    views[e] = View{normalized(T_world_head * T_head_eye), fov};
  }
  return views;
}

namespace {

std::array<View, 2> as_decoded_by_server(uint64_t frame, const std::array<View, 2>& views) {
  PoseUpdate pose;
  pose.frame = frame;
  pose.views = views;
  Datagram decoded;
  if (decode_datagram(encode_datagram(Datagram{1, 0, pose}), decoded) != DecodeError::kNone)
    throw std::logic_error("test pose does not survive the wire");
  return std::get<PoseUpdate>(decoded.message).views;
}

void take_both(client::UdpVisibilityClient& client, RunRecord& record, std::array<std::optional<Take>, 2>& last) {
  for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
    Take take;
    take.eye = eye;
    if (!client.client().take_newest(eye, take.visibility)) continue;
    take.frame = take.visibility.frame_number;
    std::optional<Take>& previous = last[static_cast<size_t>(eye)];
    if (previous) {
      const VisibilityFrame& p = previous->visibility;
      const bool newer = take.frame > p.frame_number;
      const bool more = take.frame == p.frame_number && !p.complete &&
                        (take.visibility.complete || take.visibility.rows_valid >= p.rows_valid);
      if (!newer && !more) ++record.monotonic_violations;
    }
    previous = take;
    record.takes.push_back(std::move(take));
  }
}

}  // namespace

void run_frames(client::UdpVisibilityClient& client, uint64_t frames, RunRecord& record) {
  std::array<std::optional<Take>, 2> last;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  uint64_t frame = record.last_frame_sent;
  const uint64_t end = frame + frames;
  while (frame < end && std::chrono::steady_clock::now() < deadline && !client.client().failed()) {
    client.client().tick();
    if (client.client().connected()) {
      const std::array<View, 2> views = views_for_frame(frame + 1, record.size);
      if (client.client().send_pose(FramePose{frame + 1, client.clock().now_ns(), views})) {
        ++frame;
        record.traced_views[frame] = as_decoded_by_server(frame, views);
        record.last_frame_sent = frame;
      }
    }
    take_both(client, record, last);
    std::this_thread::sleep_for(std::chrono::microseconds(11'100));
  }
}

void idle_frames(client::UdpVisibilityClient& client, int64_t duration_ns, RunRecord& record) {
  std::array<std::optional<Take>, 2> last;
  for (auto it = record.takes.rbegin(); it != record.takes.rend(); ++it)
    if (!last[static_cast<size_t>(it->eye)]) last[static_cast<size_t>(it->eye)] = *it;
  const auto end = std::chrono::steady_clock::now() + std::chrono::nanoseconds(duration_ns);
  while (std::chrono::steady_clock::now() < end) {
    client.client().tick();
    take_both(client, record, last);
    std::this_thread::sleep_for(std::chrono::microseconds(11'100));
  }
}

VisibilityBuffer reference_trace(const View& view, const EyeSize& size) {
  const Camera camera = TracedFormat{Extent{size.width, size.height}, GuardBand{size.guard_x, size.guard_y}}.camera(view);
  VisibilityBuffer out;
  server::TraceStats stats;
  TracedScene::get().tracer->trace(camera, out, stats);
  return out;
}

}  // namespace dhr::integration
