// Load and soak (docs/reliability.md): dhr-server as its own process (Embree, a deployment key, 8 sessions at
// most) and 8 real clients in this process, each sending poses at 90 Hz over loopback UDP for DHR_SOAK_SECONDS
// (default 4; DHR_SOAK_WORKERS sets the server's --workers), while a ninth socket sprays 100,000 hostile datagrams at the server (random bytes, forged
// sealed datagrams of unknown sessions, Hellos with a wrong key's tag, plain poses). Checks: the server runs
// to the end and exits cleanly; its resident memory after the warm-up grows by less than 64 MiB; every client
// keeps its one session (no failure, no restart, nothing dropped as unauthenticated on its side) and its share
// of completed frames is within 20 % of the mean; the server opened exactly the 8 sessions and dropped the
// spray. Prints one line of figures. Nothing asserts on time.
#include "child_process.hpp"
#include "loopback_rig.hpp"
#include "secure/envelope.hpp"
#include "secure/key.hpp"
#include "server_child.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

namespace dhr::integration {
namespace {

constexpr int kClients = 8;
constexpr uint64_t kSprayDatagrams = 100'000;

// VmRSS of a process in KiB (0 when unreadable).
uint64_t resident_kib(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::strtoull(line.c_str() + 6, nullptr, 10);
  return 0;
}

double soak_seconds() {
  const char* env = std::getenv("DHR_SOAK_SECONDS");
  const double s = env != nullptr ? std::atof(env) : 4.0;
  return s >= 1.0 ? s : 4.0;
}

struct ClientRun {
  client::ClientNetStats stats;
  std::string failure;
  uint64_t poses = 0;
  uint64_t takes = 0;
};

void drive(client::UdpVisibilityClient& link, const EyeSize& size, std::chrono::steady_clock::time_point end,
           uint64_t phase, ClientRun& run) {
  uint64_t frame = 0;
  while (std::chrono::steady_clock::now() < end && !link.client().failed()) {
    link.client().tick();
    if (link.client().connected() &&
        link.client().send_pose(FramePose{frame + 1, link.clock().now_ns(), views_for_frame(frame + 1 + phase, size)}))
      ++frame;
    VisibilityFrame taken;
    for (const Eye eye : {Eye::kLeft, Eye::kRight}) run.takes += link.client().take_newest(eye, taken) ? 1 : 0;
    std::this_thread::sleep_for(std::chrono::microseconds(11'100));
  }
  run.poses = frame;
  run.stats = link.client().stats();
  run.failure = link.client().failure();
}

// The hostile datagrams, deterministic.
std::vector<uint8_t> hostile(std::mt19937_64& rng, uint64_t i) {
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<uint8_t> b;
  switch (i % 4) {
    case 0: {  // random bytes, any length up to a little over the limit
      b.resize(std::uniform_int_distribution<size_t>(0, 1400)(rng));
      for (uint8_t& x : b) x = static_cast<uint8_t>(byte(rng));
      break;
    }
    case 1: {  // a sealed-looking datagram of a random session
      PoseUpdate p;
      p.frame = i + 1;
      p.views = views_for_frame(i, EyeSize{});
      b = encode_datagram(Datagram{rng() | 1, static_cast<uint32_t>(i), p});
      b[6] = static_cast<uint8_t>(secure::kFlagSealed);
      b.resize(b.size() + secure::kSealTagSize);
      for (size_t k = kHeaderSize; k < b.size(); ++k) b[k] = static_cast<uint8_t>(byte(rng));
      break;
    }
    case 2: {  // a Hello with a wrong key's tag
      static const secure::HandshakeKey wrong(secure::Key::random());
      b = encode_datagram(Datagram{0, 0, Hello{i | 1, kCapabilityLz4RowShards, 64, 48, 4, 3, 0, {}}});
      const size_t n = b.size();
      b.resize(n + secure::kHandshakeTrailerSize);
      wrong.authenticate(b, n, secure::random_bytes());
      break;
    }
    default: {  // a plain pose of a random session
      PoseUpdate p;
      p.frame = i + 1;
      p.views = views_for_frame(i, EyeSize{});
      b = encode_datagram(Datagram{rng() | 1, static_cast<uint32_t>(i), p});
      break;
    }
  }
  return b;
}

TEST(Soak, EightClientsAt90HzWithAHostileSprayStayFairBoundedAndUnharmed) {
  const double seconds = soak_seconds();
  const TempKeyFile key_file("soak");
  const std::optional<secure::Key> key = key_file.key();

  std::array<ClientRun, kClients> runs;
  uint64_t sprayed = 0;
  uint64_t rss_warm_kib = 0, rss_max_kib = 0;
  test::ChildSpec spec;
  spec.argv = {DHR_SERVER_EXE, "--scene", std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room.gltf",
               "--backend", "embree", "--port", "0", "--bind", "127.0.0.1", "--max-sessions",
               std::to_string(kClients), "--key-file", key_file.path(), "--max-seconds", std::to_string(seconds + 60.0)};
  if (const char* workers = std::getenv("DHR_SOAK_WORKERS")) {  // the server's --workers (default: its own)
    spec.argv.push_back("--workers");
    spec.argv.push_back(workers);
  }
  spec.env = {{"DHR_LOG", "error"}};
  spec.deadline = std::chrono::milliseconds(static_cast<int64_t>((seconds + 90.0) * 1000.0));
  DriveWhenListening driver([&](pid_t pid, uint16_t port) {
    const auto end = std::chrono::steady_clock::now() +
                     std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
    std::array<std::unique_ptr<client::UdpVisibilityClient>, kClients> links;
    std::vector<std::thread> threads;
    for (int c = 0; c < kClients; ++c) {
      client::VisibilityClientConfig config = client_config(EyeSize{});
      config.key = key;
      config.nonce_seed = 100 + static_cast<uint64_t>(c);
      links[static_cast<size_t>(c)] = std::make_unique<client::UdpVisibilityClient>();
      links[static_cast<size_t>(c)]->connect(config, "127.0.0.1", port);  // all before any thread: may throw
    }
    for (int c = 0; c < kClients; ++c) {
      threads.emplace_back([&, c] {
        drive(*links[static_cast<size_t>(c)], EyeSize{}, end, 37 * static_cast<uint64_t>(c), runs[static_cast<size_t>(c)]);
      });
    }
    // The spray, spread over the run; the server's memory sampled meanwhile.
    net::UdpSocket spray;
    spray.open(net::UdpSocketConfig{}, [](const net::ReceivedDatagram&) {});
    std::mt19937_64 rng(2026);
    const auto start = std::chrono::steady_clock::now();
    const auto warm_at = start + std::chrono::milliseconds(1000);
    auto next_sample = start;
    for (uint64_t i = 0; i < kSprayDatagrams; ++i) {
      const std::vector<uint8_t> b = hostile(rng, i);
      if (!b.empty() && spray.send_to(b, net::PeerAddress::loopback_ipv4(port))) ++sprayed;
      if (i % 500 == 499) {
        // Pace: all of it within ~80 % of the run.
        const auto due = start + std::chrono::duration<double>(0.8 * seconds * static_cast<double>(i + 1) /
                                                                static_cast<double>(kSprayDatagrams));
        std::this_thread::sleep_until(due);
      }
      if (std::chrono::steady_clock::now() >= next_sample) {
        const uint64_t rss = resident_kib(pid);
        rss_max_kib = std::max(rss_max_kib, rss);
        if (rss_warm_kib == 0 && std::chrono::steady_clock::now() >= warm_at) rss_warm_kib = rss;
        next_sample += std::chrono::milliseconds(100);
      }
    }
    while (std::chrono::steady_clock::now() < end) {
      rss_max_kib = std::max(rss_max_kib, resident_kib(pid));
      if (rss_warm_kib == 0 && std::chrono::steady_clock::now() >= warm_at) rss_warm_kib = resident_kib(pid);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    for (std::thread& t : threads) t.join();
    for (auto& link : links) link->close();
  });
  driver.attach(spec);
  const test::ChildResult result = test::run_child(spec);
  driver.join();

  ASSERT_TRUE(result.started) << result.err;
  ASSERT_TRUE(driver.started()) << "no 'listening on' line:\n" << result.err;
  ASSERT_TRUE(driver.failure().empty()) << driver.failure();
  EXPECT_FALSE(result.killed_at_deadline);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json server = nlohmann::json::parse(test::last_line(result.out));

  double mean = 0.0;
  for (const ClientRun& r : runs) mean += static_cast<double>(r.stats.frames_completed) / kClients;
  uint64_t lowest = UINT64_MAX, highest = 0;
  for (size_t c = 0; c < runs.size(); ++c) {
    SCOPED_TRACE("client " + std::to_string(c));
    const ClientRun& r = runs[c];
    EXPECT_TRUE(r.failure.empty()) << r.failure;
    EXPECT_EQ(r.stats.sessions_started, 1u);
    EXPECT_EQ(r.stats.sessions_restarted, 0u);
    EXPECT_EQ(r.stats.auth_failed + r.stats.replayed + r.stats.unauthenticated, 0u);
    EXPECT_GT(r.stats.frames_completed, 0u);
    EXPECT_LE(std::abs(static_cast<double>(r.stats.frames_completed) - mean), 0.2 * mean)
        << r.stats.frames_completed << " frames completed against a mean of " << mean;
    lowest = std::min(lowest, r.stats.frames_completed);
    highest = std::max(highest, r.stats.frames_completed);
  }
  EXPECT_EQ(server.at("sessions_opened").get<uint64_t>(), static_cast<uint64_t>(kClients));
  const uint64_t dropped = server.at("datagrams_rejected").get<uint64_t>();
  EXPECT_GE(dropped, sprayed * 9 / 10) << "the server saw too little of the spray";
  EXPECT_GT(rss_warm_kib, 0u);
  EXPECT_LT(rss_max_kib - std::min(rss_max_kib, rss_warm_kib), 64u * 1024u)
      << "resident memory grew from " << rss_warm_kib << " KiB to " << rss_max_kib << " KiB";
  std::printf("soak: %.0f s, %d clients, frames completed per client %llu..%llu (mean %.1f), server traced %llu, "
              "sprayed %llu, server dropped %llu (auth_failed %llu, unauthenticated %llu, unknown_token %llu), "
              "resident %llu KiB after 1 s, at most %llu KiB\n",
              seconds, kClients, static_cast<unsigned long long>(lowest), static_cast<unsigned long long>(highest),
              mean, static_cast<unsigned long long>(server.at("frames_traced").get<uint64_t>()),
              static_cast<unsigned long long>(sprayed), static_cast<unsigned long long>(dropped),
              static_cast<unsigned long long>(server.at("auth_failed").get<uint64_t>()),
              static_cast<unsigned long long>(server.at("unauthenticated").get<uint64_t>()),
              static_cast<unsigned long long>(server.at("unknown_token").get<uint64_t>()),
              static_cast<unsigned long long>(rss_warm_kib), static_cast<unsigned long long>(rss_max_kib));
}

}  // namespace
}  // namespace dhr::integration
