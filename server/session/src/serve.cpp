#include "session/serve.hpp"

#include "session/metrics_server.hpp"
#include "session/metrics_text.hpp"

#include "net/endpoints.hpp"
#include "net/impaired_sender.hpp"
#include "session/service_stats_json.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace dhr::server {

namespace {

constexpr int64_t kPaceIntervalNs = 2 * net::kNsPerMs;  // how often pace() runs

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int signal_number) { g_stop_signal = signal_number; }

// Installs SIGINT / SIGTERM handlers for its lifetime; a second signal while stopping is harmless (the
// loop is already on its way out).
class StopSignals {
 public:
  explicit StopSignals(bool install) : installed_(install) {
    g_stop_signal = 0;
    if (!installed_) return;
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~StopSignals() {
    if (!installed_) return;
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  bool installed_;
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

const char* reason_text(ByeReason reason) { return to_string(reason); }

void print_progress(const ServiceStats& s, const ServiceStats& previous, double seconds) {
  const double frames_per_s = static_cast<double>(s.frames_traced - previous.frames_traced) / seconds;
  const double mbit_per_s = static_cast<double>(s.bytes_sent - previous.bytes_sent) * 8.0 / 1e6 / seconds;
  const uint64_t eyes = 2 * (s.frames_traced - previous.frames_traced);
  const double trace_ms_per_eye = eyes ? (s.trace_ms - previous.trace_ms) / static_cast<double>(eyes) : 0.0;
  std::fprintf(stderr,
               "serve: %llu sessions, %.1f frames/s, %.2f Mbit/s, trace %.2f ms/eye, %llu poses skipped, "
               "%llu datagrams rejected\n",
               static_cast<unsigned long long>(s.sessions_active), frames_per_s, mbit_per_s, trace_ms_per_eye,
               static_cast<unsigned long long>(s.poses_skipped_identical + s.poses_superseded),
               static_cast<unsigned long long>(s.datagrams_rejected));
}

}  // namespace

int run_serve(const ServeOptions& options, VisibilityTracer& tracer) {
  if (const std::string problem = options.impairment.validate(); !problem.empty())
    throw std::runtime_error("impairment: " + problem);
  net::SteadyClock clock;
  net::ServerEndpoint endpoint;
  std::unique_ptr<net::ImpairedSender> impaired;
  if (options.impairment.active()) impaired = std::make_unique<net::ImpairedSender>(endpoint, options.impairment);
  net::DatagramSender& sender = impaired ? static_cast<net::DatagramSender&>(*impaired) : endpoint;

  VisibilityService service(tracer, options.service, sender, clock);
  service.set_session_observer([](const VisibilityService::SessionInfo& s, bool opened, ByeReason reason) {
    if (opened) {
      std::fprintf(stderr, "session %016llx opened: %s, %ux%u per eye (guard %u,%u), %u lights (%u with soft levels)\n",
                   static_cast<unsigned long long>(s.token), s.peer.to_string().c_str(), s.welcome.buffer_width,
                   s.welcome.buffer_height, s.welcome.guard_x, s.welcome.guard_y, s.welcome.light_count,
                   s.welcome.soft_light_count);
    } else {
      std::fprintf(stderr, "session %016llx closed: %s, %s, newest frame traced %llu\n",
                   static_cast<unsigned long long>(s.token), s.peer.to_string().c_str(), reason_text(reason),
                   static_cast<unsigned long long>(s.newest_frame_traced));
    }
  });

  StopSignals signals(options.handle_signals);
  net::ServerEndpointConfig endpoint_config;
  endpoint_config.bind_address = options.bind_address;
  endpoint_config.port = options.port;
  endpoint_config.max_datagram_size = kMaxDatagramSize;
  endpoint.start(endpoint_config, [&service](const net::ReceivedDatagram& d) { service.on_datagram(d.bytes, d.from); });
  std::unique_ptr<MetricsServer> metrics;
  if (options.metrics_port > 0) {
    metrics = std::make_unique<MetricsServer>(options.bind_address, options.metrics_port,
                                              [&service] { return prometheus_text(service.stats()); });
    std::fprintf(stderr, "metrics on http://%s:%u/metrics\n", options.bind_address.c_str(),
                 static_cast<unsigned>(options.metrics_port));
  }
  // The last line of the start-up: whoever waits for the port (scripts, tests) has every line above it.
  std::fprintf(stderr, "listening on %s\n", endpoint.local_address().to_string().c_str());
  std::fflush(stderr);

  std::atomic<bool> stopping{false};
  // Sessions are traced in parallel by up to `workers` threads (one session each at a time); the Vulkan
  // tracer takes one call at a time. In a moving scene the workers take turns on the tracer (the service holds
  // its tracer lock from set_scene_time through both eyes' traces).
  const uint32_t workers =
      tracer.backend() == TracerBackend::kEmbree ? std::max<uint32_t>(1, options.service.workers) : 1u;
  std::vector<std::thread> worker_threads;
  for (uint32_t i = 0; i < workers; ++i) {
    try {
      worker_threads.emplace_back([&] {
        while (!stopping.load(std::memory_order_acquire)) {
          if (service.wait_for_pending(100 * net::kNsPerMs)) service.process_pending();
        }
      });
    } catch (const std::system_error& e) {
      // The started workers are stopped and joined: a joinable std::thread destroyed would end the process.
      stopping.store(true, std::memory_order_release);
      service.interrupt_wait();
      for (std::thread& t : worker_threads) t.join();
      throw std::runtime_error("serve: cannot start worker thread " + std::to_string(i + 1) + " of " +
                               std::to_string(workers) + ": " + e.what());
    }
  }

  const int64_t start_ns = clock.now_ns();
  const int64_t limit_ns = options.max_seconds > 0.0 ? static_cast<int64_t>(options.max_seconds * 1e9) : 0;
  int64_t last_report_ns = start_ns;
  ServiceStats reported = service.stats();
  int64_t last_tick_ns = 0;
  while (g_stop_signal == 0) {
    const int64_t now = clock.now_ns();
    if (limit_ns > 0 && now - start_ns >= limit_ns) break;
    service.pace();  // every pass: rate-capped sessions' datagrams leave a few at a time
    if (last_tick_ns == 0 || now - last_tick_ns >= options.tick_interval_ns) {
      service.tick();
      last_tick_ns = now;
    }
    if (now - last_report_ns >= net::kNsPerSecond) {
      const ServiceStats s = service.stats();
      if (s.datagrams_received != reported.datagrams_received || s.sessions_active != reported.sessions_active)
        print_progress(s, reported, static_cast<double>(now - last_report_ns) / 1e9);
      reported = s;
      last_report_ns = now;
    }
    std::this_thread::sleep_for(std::chrono::nanoseconds(std::clamp<int64_t>(options.tick_interval_ns, net::kNsPerMs,
                                                                              kPaceIntervalNs)));
  }
  if (g_stop_signal != 0) std::fprintf(stderr, "serve: signal %d, shutting down\n", static_cast<int>(g_stop_signal));

  stopping.store(true, std::memory_order_release);
  service.interrupt_wait();
  for (std::thread& t : worker_threads) t.join();
  service.close_all(ByeReason::kShutdown);
  // Let the Byes out: the impairment holds them for its delay, and the socket discards what is still
  // queued when it stops.
  if (impaired) impaired->wait_idle(2 * net::kNsPerSecond);
  const uint64_t handed = impaired ? impaired->stats().forwarded : service.stats().datagrams_sent;
  for (int i = 0; i < 100; ++i) {
    const net::UdpCounters c = endpoint.counters();
    if (c.datagrams_sent + c.send_errors >= handed) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  endpoint.stop();
  impaired.reset();

  const std::string line = to_json(service.stats()).dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  std::printf("%s\n", line.c_str());
  std::fflush(stdout);
  return 0;
}

}  // namespace dhr::server
