// Helpers for the integration tests that run dhr-server as a child process: the port its "listening on"
// line names, and a deployment key file for one test (removed with it).
#pragma once
#include "child_process.hpp"
#include "secure/key.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>

namespace dhr::integration {

// The port of the first complete "listening on ADDR:PORT" line, or 0.
inline uint16_t listening_port(const std::string& err) {
  const size_t at = err.find("listening on ");
  if (at == std::string::npos) return 0;
  const size_t eol = err.find('\n', at);
  const size_t colon = err.rfind(':', eol);
  if (eol == std::string::npos || colon == std::string::npos || colon < at) return 0;
  try {
    const int port = std::stoi(err.substr(colon + 1, eol - colon - 1));
    return port > 0 && port < 65536 ? static_cast<uint16_t>(port) : 0;
  } catch (const std::exception&) {
    return 0;
  }
}

// A new deployment key in a temporary file (what dhr-server --gen-key writes), loaded; the file is removed
// on destruction. Throws std::runtime_error when it cannot be made.
class TempKeyFile {
 public:
  explicit TempKeyFile(const std::string& tag)
      : path_((std::filesystem::temp_directory_path() / ("dhr_" + tag + "_" + std::to_string(::getpid()) + ".key"))
                  .string()) {
    std::filesystem::remove(path_);
    if (const auto error = secure::generate_key_file(path_)) throw std::runtime_error(*error);
    std::string error;
    const std::optional<secure::Key> key = secure::load_key_file(path_, &error);
    if (!key) throw std::runtime_error(error);
    key_ = *key;
  }
  ~TempKeyFile() { std::filesystem::remove(path_); }
  TempKeyFile(const TempKeyFile&) = delete;
  TempKeyFile& operator=(const TempKeyFile&) = delete;
  const std::string& path() const { return path_; }
  const secure::Key& key() const { return key_; }

 private:
  std::string path_;
  secure::Key key_;
};

// Runs `body(pid, port)` on its own thread once the child dhr-server prints its "listening on" line, then
// sends the child SIGTERM whatever happened (an exception from `body` becomes failure(): the test reports it
// instead of the process ending, and the server does not wait for --max-seconds).
class DriveWhenListening {
 public:
  explicit DriveWhenListening(std::function<void(pid_t, uint16_t)> body) : body_(std::move(body)) {}
  ~DriveWhenListening() { join(); }
  DriveWhenListening(const DriveWhenListening&) = delete;
  DriveWhenListening& operator=(const DriveWhenListening&) = delete;

  void attach(test::ChildSpec& spec) {
    spec.on_output = [this](pid_t pid, const std::string&, const std::string& err) {
      if (started_) return;
      const uint16_t port = listening_port(err);
      if (port == 0) return;
      started_ = true;
      thread_ = std::thread([this, pid, port] {
        try {
          body_(pid, port);
        } catch (const std::exception& e) {
          failure_ = e.what();
        }
        kill(pid, SIGTERM);
      });
    };
  }
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  bool started() const { return started_; }
  const std::string& failure() const { return failure_; }  // after join()

 private:
  std::function<void(pid_t, uint16_t)> body_;
  std::atomic<bool> started_{false};
  std::thread thread_;
  std::string failure_;
};

}  // namespace dhr::integration
