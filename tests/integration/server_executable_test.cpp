// dhr-server --port 0 as a separate process, and the real client over loopback UDP: the executable
// prints "listening on ADDR:PORT", serves the client's poses with visibility identical to the in-process
// tracer's, and on SIGTERM says Bye, exits 0 and prints its statistics as one JSON line.
#include "child_process.hpp"
#include "loopback_rig.hpp"
#include "server_child.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

namespace dhr::integration {
namespace {

TEST(ServerExecutable, ServesTheClientAndStopsCleanlyOnSigterm) {
  RunRecord record;
  client::ClientNetStats stats;
  std::string failure;
  std::atomic<bool> client_started{false};
  std::thread client_thread;

  const TempKeyFile key("server_exe_test");  // both sides load it: the session is authenticated and sealed
  test::ChildSpec spec;
  spec.argv = {DHR_SERVER_EXE, "--scene", std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room.gltf",
               "--backend", "embree", "--port", "0", "--max-seconds", "40", "--key-file", key.path()};
  spec.env = {{"DHR_LOG", "warn"}};
  spec.deadline = std::chrono::seconds(50);
  spec.on_output = [&](pid_t pid, const std::string&, const std::string& err) {
    if (client_started) return;
    const uint16_t port = listening_port(err);
    if (port == 0) return;
    client_started = true;
    client_thread = std::thread([&, pid, port] {
      try {
        client::UdpVisibilityClient client;
        client::VisibilityClientConfig config = client_config(record.size);
        config.key = key.key();
        client.connect(config, "127.0.0.1", port);
        run_frames(client, 60, record);
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (std::chrono::steady_clock::now() < deadline) {
          const client::ClientNetStats s = client.client().stats();
          if (s.newest_frame_complete[0] == record.last_frame_sent && s.newest_frame_complete[1] == record.last_frame_sent)
            break;
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        idle_frames(client, 30 * net::kNsPerMs, record);
        stats = client.client().stats();
        failure = client.client().failure();
      } catch (const std::exception& e) {
        failure = e.what();
      }
      kill(pid, SIGTERM);  // always: the server must not wait for --max-seconds
    });
  };
  const test::ChildResult result = test::run_child(spec);
  if (client_thread.joinable()) client_thread.join();

  ASSERT_TRUE(result.started) << result.err;
  ASSERT_TRUE(client_started) << "no 'listening on' line:\n" << result.err;
  EXPECT_FALSE(result.killed_at_deadline);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(test::last_line(result.out).find("\"frames_traced\""), std::string::npos) << result.out;
  EXPECT_TRUE(failure.empty()) << failure;
  EXPECT_EQ(record.last_frame_sent, 60u);
  EXPECT_EQ(stats.sessions_started, 1u);
  EXPECT_EQ(stats.newest_frame_complete[0], 60u);
  EXPECT_EQ(stats.newest_frame_complete[1], 60u);
  EXPECT_EQ(stats.datagrams_rejected + stats.datagrams_foreign + stats.datagrams_unexpected, 0u);
  EXPECT_EQ(stats.server_datagrams_missing, 0u);
  // The other process traced the same scene with the same code: identical bits for the view each frame says it
  // was traced for. dhr-server predicts by default, so that is the view predicted from the poses sent, not the
  // pose sent; once the client moved, at least one frame must have been predicted away from its pose.
  size_t complete = 0, predicted = 0;
  for (const Take& take : record.takes) {
    if (!take.visibility.complete) continue;
    ++complete;
    const View& sent = record.traced_views.at(take.frame)[static_cast<size_t>(take.eye)];
    if (take.visibility.view.pose.position != sent.pose.position) ++predicted;
    EXPECT_TRUE(take.visibility.buffer == reference_trace(take.visibility.view, record.size)) << "frame " << take.frame;
  }
  EXPECT_GT(complete, 0u);
  EXPECT_GT(predicted, 0u) << "dhr-server's default is to trace predicted views";
}

}  // namespace
}  // namespace dhr::integration
