// A real bottleneck (docs/reliability.md): dhr-server in one network namespace, a client in another, joined by
// a veth pair whose server side sends through a kernel token bucket (tc tbf, 50 ms of queue). The client asks
// for 480x360 eyes with codec v1 (LZ4) at 90 Hz. The bucket's rate is DHR_BOTTLENECK_MBIT where set, else half of
// what the server sent in a first run through a bucket it cannot fill (1000 Mbit/s): the load then overloads the
// bucket about 2x however fast this machine traces at the time (a fixed 2 Mbit/s did not fill when other tests
// shared the 2 cores and the server sent 1.4; docs/reliability.md). Then run twice, the server's
// rate control off (--no-rate-adapt) and on: off, the bucket drops what overflows; on, the server caps the
// session's trace rate from the client's Heartbeat reports, the loss falls, more frames arrive whole and the
// response time stays bounded. Needs root and network namespaces; skipped, saying why, where they are not
// permitted.
#include "child_process.hpp"
#include "loopback_rig.hpp"
#include "secure/key.hpp"
#include "server_child.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

namespace dhr::integration {
namespace {

int sh(const std::string& command) { return std::system((command + " >/dev/null 2>&1").c_str()); }

// The bucket's rate in Mbit/s as tc takes it.
std::string rate_text(double mbit) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", mbit);
  return text;
}

// DHR_BOTTLENECK_MBIT when set to a rate in (0, 10000], else 0 (calibrate).
double rate_from_environment() {
  const char* env = std::getenv("DHR_BOTTLENECK_MBIT");
  const double mbit = env != nullptr ? std::atof(env) : 0.0;
  return mbit > 0.0 && mbit <= 10000.0 ? mbit : 0.0;
}

constexpr double kOpenMbit = 1000.0;  // a bucket the server cannot fill (the calibration run)

// Two namespaces and a veth pair, the server's end (10.77.N.1) limited by tbf; removed on destruction.
class NamespacePair {
 public:
  NamespacePair() {
    const std::string id = std::to_string(::getpid() % 100000);
    server_ns_ = "dhrsrv" + id;
    client_ns_ = "dhrcli" + id;
    const std::string a = "dva" + id, b = "dvb" + id;
    const std::string net = "10.77." + std::to_string(::getpid() % 250 + 1);
    server_address_ = net + ".1";
    const std::vector<std::string> steps = {
        "ip netns add " + server_ns_,
        "ip netns add " + client_ns_,
        "ip link add " + a + " type veth peer name " + b,
        "ip link set " + a + " netns " + server_ns_,
        "ip link set " + b + " netns " + client_ns_,
        "ip -n " + server_ns_ + " addr add " + server_address_ + "/24 dev " + a,
        "ip -n " + client_ns_ + " addr add " + net + ".2/24 dev " + b,
        "ip -n " + server_ns_ + " link set " + a + " up",
        "ip -n " + client_ns_ + " link set " + b + " up",
        "ip -n " + server_ns_ + " link set lo up",
        "ip netns exec " + server_ns_ + " tc qdisc add dev " + a + " root tbf rate " + rate_text(kOpenMbit) +
        "mbit burst 32kbit latency 50ms",
    };
    for (const std::string& step : steps) {
      if (sh(step) != 0) {
        error_ = "'" + step + "' failed";
        return;
      }
    }
    device_ = a;
    ok_ = true;
  }
  // The bucket's rate from now on (tc qdisc change); false where tc refuses it.
  bool set_rate(double mbit) const {
    return sh("ip netns exec " + server_ns_ + " tc qdisc change dev " + device_ + " root tbf rate " +
              rate_text(mbit) + "mbit burst 32kbit latency 50ms") == 0;
  }
  ~NamespacePair() {
    sh("ip netns del " + server_ns_);
    sh("ip netns del " + client_ns_);
  }
  bool ok() const { return ok_; }
  const std::string& error() const { return error_; }
  const std::string& server_ns() const { return server_ns_; }
  const std::string& client_ns() const { return client_ns_; }
  const std::string& server_address() const { return server_address_; }

 private:
  bool ok_ = false;
  std::string error_;
  std::string server_ns_, client_ns_, server_address_, device_;
};

struct Outcome {
  client::ClientNetStats client;
  std::string failure;
  nlohmann::json server;
  uint64_t poses = 0;
  // What the server sent over the client's 8 s, Mbit/s (slightly high: the server runs a little longer).
  double sent_mbit() const { return server.value("bytes_sent", 0.0) * 8e-6 / 8.0; }
  double loss() const {
    const double seen = static_cast<double>(client.server_datagrams_unique + client.server_datagrams_missing);
    return seen > 0 ? static_cast<double>(client.server_datagrams_missing) / seen : 0.0;
  }
};

Outcome run(const NamespacePair& ns, const std::string& key_path, const secure::Key& key, bool adapt) {
  Outcome outcome;
  test::ChildSpec spec;
  spec.argv = {"ip", "netns", "exec", ns.server_ns(), DHR_SERVER_EXE, "--scene",
               std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room.gltf", "--backend", "embree", "--port", "0",
               "--bind", ns.server_address(), "--key-file", key_path, "--codec", "v1", "--heartbeat-ms", "250",
               "--max-seconds", "60"};
  if (!adapt) spec.argv.push_back("--no-rate-adapt");
  spec.env = {{"DHR_LOG", "error"}};
  spec.deadline = std::chrono::seconds(90);
  DriveWhenListening driver([&](pid_t, uint16_t port) {
    // This thread joins the client's namespace: the client's socket is made there.
    const int fd = ::open(("/var/run/netns/" + ns.client_ns()).c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0 || ::setns(fd, CLONE_NEWNET) != 0) {
      outcome.failure = "cannot enter the client's namespace";
    } else {
      const EyeSize size{480, 360, 16, 12};
      client::VisibilityClientConfig config = client_config(size);
      config.key = key;
      config.codec_v2 = false;  // LZ4: more than the bucket takes at 90 Hz
      client::UdpVisibilityClient link;
      link.connect(config, ns.server_address(), port);
      const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(8);
      while (std::chrono::steady_clock::now() < end && !link.client().failed()) {
        link.client().tick();
        if (link.client().connected() &&
            link.client().send_pose(FramePose{outcome.poses + 1, link.clock().now_ns(), views_for_frame(outcome.poses + 1, size)}))
          ++outcome.poses;
        VisibilityFrame taken;
        for (const Eye eye : {Eye::kLeft, Eye::kRight}) link.client().take_newest(eye, taken);
        std::this_thread::sleep_for(std::chrono::microseconds(11'100));
      }
      outcome.client = link.client().stats();
      outcome.failure = link.client().failure();
      link.close();
    }
    if (fd >= 0) ::close(fd);
  });
  driver.attach(spec);
  const test::ChildResult result = test::run_child(spec);
  driver.join();
  EXPECT_TRUE(driver.started()) << result.err;
  EXPECT_TRUE(driver.failure().empty()) << driver.failure();
  EXPECT_EQ(result.exit_code, 0) << result.err;
  try {
    outcome.server = nlohmann::json::parse(test::last_line(result.out));
  } catch (const std::exception& e) {
    ADD_FAILURE() << "no statistics line from the server: " << e.what() << "\n" << result.out;
  }
  return outcome;
}

TEST(Bottleneck, AtTheBucketsRateTheServerCapsItsTraceRateAndFramesArriveWhole) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to make network namespaces";
  const NamespacePair ns;
  if (!ns.ok()) GTEST_SKIP() << "network namespaces or tc tbf not permitted here: " << ns.error();
  const TempKeyFile key("bottleneck");
  double mbit = rate_from_environment();
  if (mbit == 0.0) {  // half of what the server sends through a bucket it cannot fill, on this machine now
    const Outcome open = run(ns, key.path(), key.key(), false);
    ASSERT_TRUE(open.failure.empty()) << "calibration run: " << open.failure;
    mbit = 0.5 * open.sent_mbit();
    std::printf("bottleneck calibration: the server sent %.2f Mbit/s through a %g Mbit/s bucket (loss %.1f %%)\n",
                open.sent_mbit(), kOpenMbit, 100.0 * open.loss());
    ASSERT_GT(mbit, 0.1) << "the server sent almost nothing in the calibration run";
  }
  ASSERT_TRUE(ns.set_rate(mbit)) << "tc refused the bucket's rate " << rate_text(mbit) << " Mbit/s";
  const Outcome off = run(ns, key.path(), key.key(), false);
  const Outcome on = run(ns, key.path(), key.key(), true);
  for (const auto& [name, o] : {std::pair{"off", &off}, std::pair{"on", &on}}) {
    std::printf("bottleneck %s Mbit/s, rate control %s: %llu poses, server traced %llu frames, sent %.1f Mbit/s, rate decreases %llu, shed %llu; "
                "client: loss %.1f %%, frames completed %llu, evicted incomplete %llu, response mean %.1f ms (max %.1f)\n",
                rate_text(mbit).c_str(), name, static_cast<unsigned long long>(o->poses),
                static_cast<unsigned long long>(o->server.value("frames_traced", 0ull)),
                o->sent_mbit(), static_cast<unsigned long long>(o->server.value("rate_decreases", 0ull)),
                static_cast<unsigned long long>(o->server.value("datagrams_shed", 0ull)),
                100.0 * o->loss(), static_cast<unsigned long long>(o->client.frames_completed),
                static_cast<unsigned long long>(o->client.frames_evicted), o->client.response.mean_ns() * 1e-6,
                o->client.response.max_ns * 1e-6);
    EXPECT_TRUE(o->failure.empty()) << name << ": " << o->failure;
  }
  // The load exceeds the bucket: without rate control it drops a good part of what the server sends.
  EXPECT_GT(off.loss(), 0.10) << "the load did not exceed the bottleneck: the test shows nothing";
  // With it, the server lowered the session's rate, the loss fell and more frames arrived whole.
  EXPECT_GE(on.server.value("rate_decreases", 0ull), 1ull);
  EXPECT_LT(on.loss(), off.loss() / 2);
  EXPECT_GT(on.client.frames_completed, off.client.frames_completed);
  EXPECT_GT(on.client.response.count, 0u);
}

}  // namespace
}  // namespace dhr::integration
