// Helpers for the integration tests that run dhr-server as a child process: the port its "listening on"
// line names, and a deployment key file for one test (removed with it).
#pragma once
#include "secure/key.hpp"

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

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

}  // namespace dhr::integration
