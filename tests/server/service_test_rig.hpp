// Test rig for VisibilityService: the real Embree tracer on the default room (built once), a
// SimulatedLink carrying the server's datagrams and a VirtualClock; clients are peer addresses whose
// datagrams go straight into on_datagram.
#pragma once
#include "scene/camera_bookmarks.hpp"
#include "codec/reassembly.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "net/simulated_link.hpp"
#include "scene/scene_hash.hpp"
#include "session/service_stats_json.hpp"
#include "session/visibility_service.hpp"
#include "test_scenes.hpp"

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>

namespace dhr::server::test_rig {

inline constexpr uint16_t kEyeW = 64, kEyeH = 48, kGuardX = 4, kGuardY = 3;

struct SharedScene {
  Scene scene;
  std::unique_ptr<EmbreeTracer> tracer;
};

// The loaded scene and an Embree tracer (2 threads) over it, kept under `key` from the first call on; `load` runs
// on the first call only. Throws with the loader's message.
template <class Load>
SharedScene& kept_scene(const std::string& key, Load load) {
  static auto* scenes = new std::map<std::string, std::unique_ptr<SharedScene>>;
  std::unique_ptr<SharedScene>& slot = (*scenes)[key];
  if (!slot) {
    SceneLoadResult loaded = load();
    if (!loaded) throw std::runtime_error(loaded.error);
    slot = std::make_unique<SharedScene>();
    slot->scene = std::move(*loaded.scene);
    TracerOptions options;
    options.threads = 2;
    slot->tracer = std::make_unique<EmbreeTracer>(slot->scene, options);
  }
  return *slot;
}

// One loaded scene and its tracer per scene file (relative to the source tree), made on first use and kept.
inline SharedScene& shared_scene(const std::string& path = kDefaultScenePath) {
  return kept_scene(path, [&] { return load_scene(test::source_path(path)); });
}

// A scene a test wrote as glTF text (`name` stands for its file) and its tracer, made on first use and kept.
inline SharedScene& shared_scene_from_text(const std::string& name, const std::string& gltf_text) {
  return kept_scene("text:" + name,
                    [&] { return load_scene_from_memory(gltf_text.data(), gltf_text.size(), ".", name); });
}

// Both eyes from above and in front of a floor around the origin (y = 0), looking at its centre.
inline std::array<View, 2> floor_views() {
  const Pose head = look_at_pose(CameraBookmark{"floor", {0.0, 3.0, 4.0}, {0.0, 0.0, 0.0}}).value();
  const Fov fov = symmetric_fov(90.0, Extent{kEyeW, kEyeH});
  return {View{left_eye_pose(head), fov}, View{left_eye_pose(head, -kDefaultIpdMetres), fov}};
}

inline std::array<View, 2> bookmark_views(size_t index, double shift_x = 0.0) {
  std::string error;
  const auto bookmarks =
      load_camera_bookmarks(camera_bookmarks_path(test::source_path(kDefaultScenePath)), &error).value();
  CameraBookmark b = bookmarks.at(index % bookmarks.size());
  b.position.x += shift_x;
  b.target.x += shift_x;
  const Pose head = look_at_pose(b).value();
  const Fov fov = symmetric_fov(90.0, Extent{kEyeW, kEyeH});
  return {View{left_eye_pose(head), fov}, View{left_eye_pose(head, -kDefaultIpdMetres), fov}};
}

inline Hello make_hello(uint64_t nonce, uint8_t lights = 0) {
  Hello h;
  h.client_nonce = nonce;
  h.eye_width = kEyeW;
  h.eye_height = kEyeH;
  h.guard_x = kGuardX;
  h.guard_y = kGuardY;
  h.light_count_wanted = lights;
  return h;
}

class VisibilityServiceTest : public ::testing::Test {
 protected:
  void SetUp() override { serve("default_room", shared_scene(), 42); }

  // The service for `scene` under `scene_id`, with the rig's session limits.
  void serve(const std::string& scene_id, SharedScene& scene, uint64_t token_seed) {
    scene_ = &scene;
    config_.scene_id = scene_id;
    config_.scene_hash = scene_content_hash(scene.scene);
    config_.max_sessions = 4;
    config_.session_timeout_ns = 5 * net::kNsPerSecond;
    config_.heartbeat_interval_ns = net::kNsPerSecond;
    config_.token_seed = token_seed;
    make_service();
  }

  void make_service() {
    service_.reset();
    service_ = std::make_unique<VisibilityService>(*scene_->tracer, config_, link_, clock_);
  }

  SharedScene* scene_ = nullptr;  // what serve() serves

  static net::PeerAddress peer(uint8_t i, uint16_t port = 5000) { return net::PeerAddress::ipv4({10, 0, 0, i}, port); }

  void send(const Datagram& d, const net::PeerAddress& from) {
    const std::vector<uint8_t> bytes = encode_datagram(d);
    ASSERT_FALSE(bytes.empty());
    service_->on_datagram(bytes, from);
  }
  void send_raw(const std::vector<uint8_t>& bytes, const net::PeerAddress& from) { service_->on_datagram(bytes, from); }

  // Everything the server sent, per destination, decoded.
  std::map<net::PeerAddress, std::vector<Datagram>> drain() {
    std::map<net::PeerAddress, std::vector<Datagram>> out;
    link_.deliver_due([&](const net::SimulatedDelivery& d) {
      Datagram dg;
      EXPECT_EQ(decode_datagram(d.bytes, dg), DecodeError::kNone);
      out[d.to].push_back(std::move(dg));
    });
    return out;
  }

  // Hello -> Welcome; returns the token.
  uint64_t connect(const net::PeerAddress& from, uint64_t nonce, Welcome* out_welcome = nullptr, uint8_t lights = 0) {
    send(Datagram{0, 0, make_hello(nonce, lights)}, from);
    auto sent = drain();
    EXPECT_EQ(sent[from].size(), 1u);
    if (sent[from].empty()) return 0;
    const auto* w = std::get_if<Welcome>(&sent[from][0].message);
    EXPECT_NE(w, nullptr);
    if (!w) return 0;
    if (out_welcome) *out_welcome = *w;
    return sent[from][0].session_token;
  }

  // Sends a pose (displayed at `scene_time_ns`); returns the views as the server decodes them (renormalized).
  std::array<View, 2> send_pose(uint64_t token, const net::PeerAddress& from, uint64_t frame,
                                const std::array<View, 2>& views, int64_t scene_time_ns = 0) {
    PoseUpdate p;
    p.frame = frame;
    p.display_time_ns = static_cast<int64_t>(frame) * 11'000'000;
    p.scene_time_ns = scene_time_ns;
    p.views = views;
    const std::vector<uint8_t> bytes = encode_datagram(Datagram{token, static_cast<uint32_t>(frame), p});
    Datagram decoded;
    EXPECT_EQ(decode_datagram(bytes, decoded), DecodeError::kNone);
    service_->on_datagram(bytes, from);
    return std::get<PoseUpdate>(decoded.message).views;
  }

  static std::vector<VisibilityShard> shards_of(const std::vector<Datagram>& datagrams) {
    std::vector<VisibilityShard> out;
    for (const Datagram& d : datagrams)
      if (const auto* s = std::get_if<VisibilityShard>(&d.message)) out.push_back(*s);
    return out;
  }
  static std::vector<Bye> byes_of(const std::vector<Datagram>& datagrams) {
    std::vector<Bye> out;
    for (const Datagram& d : datagrams)
      if (const auto* b = std::get_if<Bye>(&d.message)) out.push_back(*b);
    return out;
  }

  // Reassembles the shards of one frame for both eyes.
  static std::array<VisibilityBuffer, 2> reassemble(const Welcome& w, const std::vector<VisibilityShard>& shards,
                                                    uint64_t frame, std::array<View, 2>* out_views = nullptr) {
    ReassemblerConfig rc;
    rc.width = w.buffer_width;
    rc.height = w.buffer_height;
    rc.light_count = w.used_mask_bits();
    VisibilityReassembler reassembler(rc);
    for (const VisibilityShard& s : shards) {
      const InsertResult r = reassembler.insert(s);
      EXPECT_TRUE(r.status == InsertStatus::kAccepted || r.status == InsertStatus::kCompleted) << to_string(r.status);
    }
    std::array<VisibilityBuffer, 2> out;
    for (int e = 0; e < 2; ++e) {
      const ReassembledFrame* f = reassembler.latest_complete(static_cast<Eye>(e));
      EXPECT_NE(f, nullptr);
      if (!f) continue;
      EXPECT_EQ(f->visibility.frame_number, frame);
      out[e] = f->visibility.buffer;
      if (out_views) (*out_views)[e] = f->visibility.view;
    }
    return out;
  }

  static VisibilityBuffer trace_directly(const View& view) {
    VisibilityBuffer out;
    TraceStats stats;
    shared_scene().tracer->trace(TracedFormat{Extent{kEyeW, kEyeH}, GuardBand{kGuardX, kGuardY}}.camera(view), out, stats);
    return out;
  }

  ServiceConfig config_;
  net::VirtualClock clock_{1'000'000'000};
  net::SimulatedLink link_{net::ImpairmentParams{}, clock_};
  std::unique_ptr<VisibilityService> service_;
};

}  // namespace dhr::server::test_rig
