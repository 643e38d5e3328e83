// Loopback rig for the integration tests: the real server (VisibilityService on a real ServerEndpoint
// bound to 127.0.0.1, port 0, one worker thread that traces and ticks, optional ImpairedSender on its
// send side) with the Embree tracer on the default room, and a render-loop driver for the real client
// (UdpVisibilityClient) that sends a pose sequence and records everything take_newest() hands out.
#pragma once
#include <functional>
#include "protocol/protocol.hpp"
#include "scene/scene.hpp"
#include "net/endpoints.hpp"
#include "net/impaired_sender.hpp"
#include "link/udp_visibility_client.hpp"
#include "session/visibility_service.hpp"
#include "trace/visibility_tracer.hpp"

#include <array>
#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

namespace dhr::integration {

struct EyeSize {
  uint16_t width = 64;
  uint16_t height = 48;
  uint16_t guard_x = 4;  // per side
  uint16_t guard_y = 3;
};

// The default room and an Embree tracer over it, shared by every test of the process.
struct TracedScene {
  Scene scene;
  std::unique_ptr<server::VisibilityTracer> tracer;
  static TracedScene& get();  // loads once; throws with the loader's message on failure
};

class LoopbackServer {
 public:
  // `tweak` may change the service's configuration (codec, shard size) before it starts.
  LoopbackServer(server::VisibilityTracer& tracer, const net::ImpairmentParams& impairment = {},
                 const std::function<void(server::ServiceConfig&)>& tweak = {});
  ~LoopbackServer();  // stop()
  // Joins the worker (nothing new is sent), lets the impairment layer and the socket's send queue drain
  // (bounded waits), then stops the socket. No Bye: the tests check the client's counters afterwards.
  void stop();

  uint16_t port() const { return endpoint_.port(); }
  net::UdpCounters udp_counters() const { return endpoint_.counters(); }
  server::VisibilityService& service() { return *service_; }
  std::optional<net::ImpairedSenderStats> impairment_stats() const;

 private:
  net::SteadyClock clock_;
  net::ServerEndpoint endpoint_;
  std::unique_ptr<net::ImpairedSender> impaired_;
  std::unique_ptr<server::VisibilityService> service_;
  std::atomic<bool> stopping_{false};
  std::thread worker_;
};

// One take_newest() result, kept for checking after the run.
struct Take {
  uint64_t frame = 0;
  Eye eye = Eye::kLeft;
  VisibilityFrame visibility;
};

struct RunRecord {
  EyeSize size;
  std::vector<Take> takes;
  // Per frame sent: the views exactly as the server decodes them (the wire quantizes orientations).
  std::map<uint64_t, std::array<View, 2>> traced_views;
  uint64_t last_frame_sent = 0;
  size_t monotonic_violations = 0;  // take_newest() handed an older frame, or the same one without more data
};

client::VisibilityClientConfig client_config(const EyeSize& size);

// Head pose of frame f: a slow sideways sweep through the room, looking at the table; eyes +-IPD/2.
std::array<View, 2> views_for_frame(uint64_t frame, const EyeSize& size);

// The render loop: tick, send a pose per frame while connected, take the newest visibility of each eye,
// ~90 Hz (sleeps; nothing asserts on time). Stops after `frames` poses were sent or when the client
// failed or 30 s passed.
void run_frames(client::UdpVisibilityClient& client, uint64_t frames, RunRecord& record);
// Keeps ticking and taking (no new poses) for `duration_ns` (lets incomplete frames go quiet).
void idle_frames(client::UdpVisibilityClient& client, int64_t duration_ns, RunRecord& record);

// The server's reference: the tracer's direct output for one eye of the view the server decoded.
VisibilityBuffer reference_trace(const View& view, const EyeSize& size);

}  // namespace dhr::integration
