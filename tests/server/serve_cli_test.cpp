// dhr-server --port: starts, names its port, answers a real Hello over loopback UDP, stops on
// --max-seconds or SIGTERM with Bye(shutdown) and a JSON stats line; bad serving options exit 2; --gen-key
// writes a private key once; with --key-file only an authenticated Hello gets a (tagged) Welcome.
#include "protocol/protocol.hpp"
#include "net/udp_socket.hpp"
#include "secure/envelope.hpp"
#include "secure/key.hpp"
#include "test_scenes.hpp"
#include <glm/gtc/quaternion.hpp>
#include <sys/stat.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

extern char** environ;

namespace dhr::server {
namespace {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// dhr-server with stdout and stderr captured in files.
class ServerProcess {
 public:
  explicit ServerProcess(const std::vector<std::string>& args) {
    const auto dir = std::filesystem::temp_directory_path();
    const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(counter_++);
    out_path_ = dir / ("dhr_serve_out_" + tag);
    err_path_ = dir / ("dhr_serve_err_" + tag);
    std::vector<std::string> argv_storage{DHR_SERVER_EXE};
    argv_storage.insert(argv_storage.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : argv_storage) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, err_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (posix_spawn(&pid_, DHR_SERVER_EXE, &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  ~ServerProcess() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    std::filesystem::remove(out_path_);
    std::filesystem::remove(err_path_);
  }

  bool started() const { return pid_ > 0; }
  // The port from "listening on ADDR:PORT", or 0 when the line did not appear in time / the process ended.
  uint16_t wait_for_port(std::chrono::seconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      const std::string err = read_file(err_path_);
      const size_t at = err.find("listening on ");
      const size_t eol = at == std::string::npos ? at : err.find('\n', at);
      if (eol != std::string::npos) {
        const std::string addr = err.substr(at + 13, eol - at - 13);
        return static_cast<uint16_t>(std::stoi(addr.substr(addr.rfind(':') + 1)));
      }
      if (poll_exit()) return 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return 0;
  }
  int wait_exit(std::chrono::seconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!poll_exit() && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return exited_ ? exit_code_ : -1;
  }
  void signal(int sig) { ::kill(pid_, sig); }
  std::string out() const { return read_file(out_path_); }
  std::string err() const { return read_file(err_path_); }

 private:
  bool poll_exit() {
    if (exited_) return true;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) != pid_) return false;
    exited_ = true;
    exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return true;
  }

  static inline int counter_ = 0;
  pid_t pid_ = -1;
  bool exited_ = false;
  int exit_code_ = -1;
  std::filesystem::path out_path_, err_path_;
};

// A bare UDP client collecting decoded datagrams.
struct Client {
  net::UdpSocket socket;
  std::mutex mutex;
  std::vector<Datagram> received;
  std::vector<std::vector<uint8_t>> raw;  // everything, as it arrived

  Client() {
    socket.open(net::UdpSocketConfig{}, [this](const net::ReceivedDatagram& d) {
      std::lock_guard lock(mutex);
      raw.emplace_back(d.bytes.begin(), d.bytes.end());
      Datagram dg;
      if (decode_datagram(d.bytes, dg) != DecodeError::kNone) return;
      received.push_back(dg);
    });
  }
  std::optional<std::vector<uint8_t>> wait_raw(std::chrono::seconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      {
        std::lock_guard lock(mutex);
        if (!raw.empty()) return raw.front();
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return std::nullopt;
  }
  template <class T>
  std::optional<std::pair<uint64_t, T>> wait_for(std::chrono::seconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      {
        std::lock_guard lock(mutex);
        for (const Datagram& d : received)
          if (const auto* m = std::get_if<T>(&d.message)) return std::make_pair(d.session_token, *m);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return std::nullopt;
  }
};

Hello small_hello() {
  Hello h;
  h.client_nonce = 0x1234;
  h.eye_width = 32;
  h.eye_height = 24;
  h.guard_x = 2;
  h.guard_y = 2;
  return h;
}

nlohmann::json last_json_line(const std::string& out) {
  std::stringstream ss(out);
  std::string line, last;
  while (std::getline(ss, line))
    if (!line.empty()) last = line;
  return nlohmann::json::parse(last);
}

TEST(ServeCli, ServesAHelloAndStopsAfterMaxSeconds) {
  ServerProcess server({"--port", "0", "--bind", "127.0.0.1", "--max-seconds", "3", "--insecure", "--encode-threads", "1"});
  ASSERT_TRUE(server.started());
  const uint16_t port = server.wait_for_port(std::chrono::seconds(60));
  ASSERT_NE(port, 0) << server.err();
  Client client;
  const std::vector<uint8_t> hello = encode_datagram(Datagram{0, 0, small_hello()});
  ASSERT_TRUE(client.socket.send_to(hello, net::PeerAddress::loopback_ipv4(port)));
  const auto welcome = client.wait_for<Welcome>(std::chrono::seconds(5));
  ASSERT_TRUE(welcome) << server.err();
  EXPECT_NE(welcome->first, 0u);
  EXPECT_EQ(welcome->second.client_nonce, 0x1234u);
  EXPECT_EQ(welcome->second.buffer_width, 36);
  EXPECT_EQ(welcome->second.buffer_height, 28);
  EXPECT_GT(welcome->second.light_count, 0);
  EXPECT_NE(welcome->second.scene_hash, 0u);
  ASSERT_EQ(server.wait_exit(std::chrono::seconds(30)), 0) << server.err();
  const auto bye = client.wait_for<Bye>(std::chrono::seconds(2));
  ASSERT_TRUE(bye);
  EXPECT_EQ(bye->second.reason, ByeReason::kShutdown);
  EXPECT_EQ(bye->first, welcome->first);
  const nlohmann::json stats = last_json_line(server.out());
  EXPECT_EQ(stats.at("hellos").get<int>(), 1);
  EXPECT_EQ(stats.at("sessions_opened").get<int>(), 1);
  EXPECT_EQ(stats.at("sessions_closed").get<int>(), 1);
  EXPECT_NE(server.err().find("session "), std::string::npos);
}

// The codec's row ranges follow --encode-threads from 2 to 4 unless --encode-ranges says otherwise; the serving
// lines say what was set.
TEST(ServeCli, EncodeRangesFollowTheThreadsUpToFour) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--encode-threads", "1"}, "in 2 row ranges, coded on up to 1 threads"},
      {{"--encode-threads", "3"}, "in 3 row ranges, coded on up to 3 threads"},
      {{"--encode-threads", "8"}, "in 4 row ranges, coded on up to 8 threads"},
      {{"--encode-threads", "2", "--encode-ranges", "6"}, "in 6 row ranges, coded on up to 2 threads"},
  };
  for (const auto& [extra, expected] : cases) {
    std::vector<std::string> args = {"--port", "0", "--bind", "127.0.0.1", "--max-seconds", "1", "--insecure"};
    args.insert(args.end(), extra.begin(), extra.end());
    ServerProcess server(args);
    ASSERT_TRUE(server.started());
    ASSERT_EQ(server.wait_exit(std::chrono::seconds(60)), 0) << server.err();
    EXPECT_NE(server.err().find("codec v2: each eye frame " + expected), std::string::npos) << server.err();
  }
}

// A client offering soft levels, served the area-light scene: the Welcome grants them (2 of 3 lights: 7 bits), the
// serving line names the layout, and the statistics count the soft session; --soft-levels off grants none.
TEST(ServeCli, SoftLevelsAreGrantedOnTheAreaLightScene) {
  for (const bool on : {true, false}) {
    ServerProcess server({"--port", "0", "--bind", "127.0.0.1", "--max-seconds", "2", "--insecure", "--scene",
                          dhr::test::source_path("assets/scenes/default_room_area.gltf"), "--soft-levels",
                          on ? "on" : "off"});
    ASSERT_TRUE(server.started());
    const uint16_t port = server.wait_for_port(std::chrono::seconds(60));
    ASSERT_NE(port, 0) << server.err();
    Client client;
    Hello hello = small_hello();
    hello.capabilities |= kCapabilityCodecV2 | kCapabilitySoftLevels;
    ASSERT_TRUE(client.socket.send_to(encode_datagram(Datagram{0, 0, hello}), net::PeerAddress::loopback_ipv4(port)));
    const auto welcome = client.wait_for<Welcome>(std::chrono::seconds(5));
    ASSERT_TRUE(welcome) << server.err();
    EXPECT_EQ((welcome->second.capabilities & kCapabilitySoftLevels) != 0, on);
    EXPECT_EQ(welcome->second.soft_light_count, on ? 2 : 0);
    EXPECT_EQ(welcome->second.used_mask_bits(), on ? 7u : 3u);
    ASSERT_EQ(server.wait_exit(std::chrono::seconds(30)), 0) << server.err();
    EXPECT_NE(server.err().find(on ? "mask layout: soft levels for clients that offer them: 'ceiling_panel' bits 0-2"
                                   : "mask layout: one bit per light (--soft-levels off)"),
              std::string::npos)
        << server.err();
    EXPECT_EQ(last_json_line(server.out()).at("sessions_soft").get<int>(), on ? 1 : 0);
  }
}

// The moving living room: the Embree backend plays its animations on the scene clock and says so; the statistics
// carry the scene-time fields.
TEST(ServeCli, AMovingSceneIsPlayedOnTheSceneClock) {
  const std::string path = dhr::test::shared_data_path("scenes/living_room_moving.glb");
  if (path.empty()) GTEST_SKIP() << "../shared/data not present";
  ServerProcess server({"--port", "0", "--bind", "127.0.0.1", "--max-seconds", "1", "--insecure", "--backend",
                        "embree", "--scene", path});
  ASSERT_TRUE(server.started());
  ASSERT_EQ(server.wait_exit(std::chrono::seconds(120)), 0) << server.err();
  EXPECT_NE(server.err().find("scene: 1 animation(s), 3 track(s) play on the scene clock"), std::string::npos)
      << server.err();
  EXPECT_EQ(server.err().find("not played"), std::string::npos) << server.err();
  const auto stats = last_json_line(server.out());
  EXPECT_EQ(stats.at("frames_at_scene_time").get<int>(), 0);
  EXPECT_TRUE(stats.contains("scene_update_ms_per_frame"));
  EXPECT_TRUE(stats.contains("trace_gpu_ms"));
}

TEST(ServeCli, ImpairedSendsStillDeliverTheFinalBye) {
  // 40 ms delay on everything sent: the Welcome arrives late, and shutdown waits for the held Bye.
  ServerProcess server({"--port", "0", "--bind", "127.0.0.1", "--max-seconds", "2", "--net-delay", "40", "--insecure"});
  ASSERT_TRUE(server.started());
  const uint16_t port = server.wait_for_port(std::chrono::seconds(60));
  ASSERT_NE(port, 0) << server.err();
  Client client;
  ASSERT_TRUE(client.socket.send_to(encode_datagram(Datagram{0, 0, small_hello()}), net::PeerAddress::loopback_ipv4(port)));
  ASSERT_TRUE(client.wait_for<Welcome>(std::chrono::seconds(5))) << server.err();
  ASSERT_EQ(server.wait_exit(std::chrono::seconds(30)), 0) << server.err();
  const auto bye = client.wait_for<Bye>(std::chrono::seconds(2));
  ASSERT_TRUE(bye) << server.err();
  EXPECT_EQ(bye->second.reason, ByeReason::kShutdown);
  EXPECT_NE(server.err().find("impairment on send: delay=40"), std::string::npos) << server.err();
}

TEST(ServeCli, HelpDescribesServing) {
  ServerProcess server({"--help"});
  ASSERT_EQ(server.wait_exit(std::chrono::seconds(30)), 0);
  for (const char* option : {"--port", "--bind", "--max-seconds", "--max-sessions", "--net-delay", "--net-loss"})
    EXPECT_NE(server.out().find(option), std::string::npos) << option;
}

TEST(ServeCli, SigtermStopsCleanly) {
  ServerProcess server({"--port", "0", "--bind", "127.0.0.1", "--insecure"});
  ASSERT_TRUE(server.started());
  ASSERT_NE(server.wait_for_port(std::chrono::seconds(60)), 0) << server.err();
  server.signal(SIGTERM);
  ASSERT_EQ(server.wait_exit(std::chrono::seconds(30)), 0) << server.err();
  const nlohmann::json stats = last_json_line(server.out());
  EXPECT_EQ(stats.at("sessions_opened").get<int>(), 0);
  EXPECT_TRUE(stats.contains("datagrams_received"));
}

TEST(ServeCli, GenKeyOnceAndOnlyAuthenticatedHellosAreWelcomed) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("dhr_serve_key_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string key_path = (dir / "dhr.key").string();
  {
    ServerProcess gen({"--gen-key", key_path});
    ASSERT_EQ(gen.wait_exit(std::chrono::seconds(30)), 0) << gen.err();
    struct stat st {};
    ASSERT_EQ(::stat(key_path.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600u);
    ServerProcess again({"--gen-key", key_path});
    EXPECT_EQ(again.wait_exit(std::chrono::seconds(30)), 2);
    EXPECT_NE(again.err().find("exists"), std::string::npos) << again.err();
  }
  std::string error;
  const std::optional<secure::Key> key = secure::load_key_file(key_path, &error);
  ASSERT_TRUE(key) << error;

  ServerProcess server({"--port", "0", "--bind", "127.0.0.1", "--max-seconds", "3", "--key-file", key_path});
  ASSERT_TRUE(server.started());
  const uint16_t port = server.wait_for_port(std::chrono::seconds(60));
  ASSERT_NE(port, 0) << server.err();
  EXPECT_NE(server.err().find("authentication on"), std::string::npos) << server.err();
  {  // A plain Hello: Bye(authentication required), in the clear.
    Client plain;
    ASSERT_TRUE(plain.socket.send_to(encode_datagram(Datagram{0, 0, small_hello()}), net::PeerAddress::loopback_ipv4(port)));
    const auto bye = plain.wait_for<Bye>(std::chrono::seconds(5));
    ASSERT_TRUE(bye) << server.err();
    EXPECT_EQ(bye->second.reason, ByeReason::kAuthRequired);
  }
  {  // An authenticated Hello: a Welcome whose tag verifies against this Hello's random.
    Client client;
    std::array<uint8_t, kMaxDatagramSize> hello{};
    const size_t plain_size = encode_datagram(Datagram{0, 0, small_hello()}, hello);
    const secure::HandshakeKey hs(*key);
    const secure::Random random = secure::random_bytes();
    const size_t n = hs.authenticate(hello, plain_size, random);
    ASSERT_GT(n, 0u);
    ASSERT_TRUE(client.socket.send_to(std::span<const uint8_t>(hello.data(), n), net::PeerAddress::loopback_ipv4(port)));
    const std::optional<std::vector<uint8_t>> raw = client.wait_raw(std::chrono::seconds(5));
    ASSERT_TRUE(raw) << server.err();
    std::array<uint8_t, kMaxDatagramSize> plain{};
    const auto verified = hs.verify(*raw, plain, random);
    ASSERT_TRUE(verified) << "the Welcome's tag does not verify";
    Datagram welcome;
    ASSERT_EQ(decode_datagram(std::span<const uint8_t>(plain.data(), verified->size), welcome), DecodeError::kNone);
    ASSERT_TRUE(std::holds_alternative<Welcome>(welcome.message));
    EXPECT_EQ(std::get<Welcome>(welcome.message).client_nonce, 0x1234u);
  }
  ASSERT_EQ(server.wait_exit(std::chrono::seconds(30)), 0) << server.err();
  const nlohmann::json stats = last_json_line(server.out());
  EXPECT_EQ(stats.at("unauthenticated").get<int>(), 1);
  EXPECT_EQ(stats.at("sessions_opened").get<int>(), 1);
  std::filesystem::remove_all(dir);
}

// A free TCP port on 127.0.0.1 (bound, read back, released).
uint16_t free_tcp_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof addr;
  uint16_t port = 0;
  if (fd >= 0 && ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0)
    port = ntohs(addr.sin_port);
  if (fd >= 0) ::close(fd);
  return port;
}

// GET path over HTTP/1.0 from 127.0.0.1:port; the whole response (headers and body), "" on failure.
std::string http_get(uint16_t port, const std::string& path) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(port);
  std::string response;
  if (fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    const std::string request = "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n";
    if (::send(fd, request.data(), request.size(), 0) == static_cast<ssize_t>(request.size())) {
      char buffer[4096];
      for (ssize_t n; (n = ::recv(fd, buffer, sizeof buffer, 0)) > 0;) response.append(buffer, static_cast<size_t>(n));
    }
  }
  if (fd >= 0) ::close(fd);
  return response;
}

TEST(ServeCli, MetricsPortServesPrometheusTextOfTheRunningServer) {
  const uint16_t metrics_port = free_tcp_port();
  ASSERT_NE(metrics_port, 0);
  ServerProcess server({"--port", "0", "--bind", "127.0.0.1", "--max-seconds", "4", "--insecure", "--metrics-port",
                        std::to_string(metrics_port)});
  ASSERT_TRUE(server.started());
  const uint16_t port = server.wait_for_port(std::chrono::seconds(60));
  ASSERT_NE(port, 0) << server.err();
  EXPECT_NE(server.err().find("metrics on http://127.0.0.1:" + std::to_string(metrics_port) + "/metrics"),
            std::string::npos) << server.err();
  Client client;
  ASSERT_TRUE(client.socket.send_to(encode_datagram(Datagram{0, 0, small_hello()}), net::PeerAddress::loopback_ipv4(port)));
  ASSERT_TRUE(client.wait_for<Welcome>(std::chrono::seconds(5))) << server.err();
  // A pose of a session the server does not know: dropped as unknown_token.
  PoseUpdate pose;
  pose.frame = 1;
  pose.views[0].pose.orientation = glm::dquat(1, 0, 0, 0);
  pose.views[1] = pose.views[0];
  pose.views[0].fov = pose.views[1].fov = Fov{-0.7f, 0.7f, 0.6f, -0.6f};
  ASSERT_TRUE(client.socket.send_to(encode_datagram(Datagram{12345, 0, pose}), net::PeerAddress::loopback_ipv4(port)));
  std::string response;
  for (int i = 0; i < 50; ++i) {  // until the drop is counted
    response = http_get(metrics_port, "/metrics");
    if (response.find("dhr_datagrams_dropped_total{reason=\"unknown_token\"} 1") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_NE(response.find("HTTP/1.1 200 OK"), std::string::npos) << response;
  EXPECT_NE(response.find("Content-Type: text/plain; version=0.0.4"), std::string::npos) << response;
  for (const char* line : {"dhr_sessions_active 1", "dhr_sessions_opened_total 1",
                           "dhr_datagrams_dropped_total{reason=\"unknown_token\"} 1", "dhr_auth_failures_total 0",
                           "# TYPE dhr_trace_ms histogram", "dhr_response_ms_bucket{le=\"+Inf\"} 0"})
    EXPECT_NE(response.find(line), std::string::npos) << line << "\n" << response;
  EXPECT_NE(http_get(metrics_port, "/elsewhere").find("404"), std::string::npos);
  ASSERT_EQ(server.wait_exit(std::chrono::seconds(30)), 0) << server.err();
}

TEST(ServeCli, BadServingOptionsExitTwo) {
  struct Case {
    std::vector<std::string> args;
    std::string expected;  // in stderr
  };
  const std::vector<Case> cases = {
      {{"--port", "70000"}, "--port: expected an integer 0..65535, got '70000'"},
      {{"--port", "abc"}, "--port: expected an integer 0..65535, got 'abc'"},
      {{"--port", "0", "--insecure", "--net-loss", "2"}, "--net-loss"},
      {{"--port", "0", "--insecure", "--check"}, "--check"},
      {{"--port", "0", "--insecure", "--max-sessions", "0"}, "--max-sessions"},
      {{"--port", "0", "--insecure", "--encode-threads", "0"}, "--encode-threads"},
      {{"--port", "0", "--insecure", "--encode-ranges", "65"}, "--encode-ranges"},
      {{"--port", "0", "--insecure", "--bind", "not-an-address"}, "not-an-address"},
      {{"--port", "0"}, "serving needs a key: --key-file FILE"},
      {{"--port", "0", "--insecure", "--key-file", "k"}, "--key-file and --insecure exclude each other"},
      {{"--port", "0", "--key-file", "/nonexistent/dhr.key"}, "cannot read key file /nonexistent/dhr.key"},
      {{"--gen-key", "/nonexistent/dir/dhr.key"}, "--gen-key: cannot create /nonexistent/dir/dhr.key"},
  };
  for (const Case& c : cases) {
    ServerProcess server(c.args);
    ASSERT_TRUE(server.started());
    EXPECT_EQ(server.wait_exit(std::chrono::seconds(60)), 2) << c.args.back() << ": " << server.err();
    EXPECT_NE(server.err().find(c.expected), std::string::npos) << server.err();
    EXPECT_TRUE(server.out().empty()) << server.out();
  }
}

}  // namespace
}  // namespace dhr::server
