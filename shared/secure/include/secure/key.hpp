// The deployment key (pairing): 32 random bytes both the server and its headsets hold, in a key file of one
// line "dhr-xr-key-1 <64 hex digits>" (lines starting with '#' are comments), readable by its owner only.
// docs/security.md has the threat model.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace dhr::secure {

inline constexpr size_t kKeySize = 32;

// A secret key: wiped when destroyed.
class Key {
 public:
  Key() { bytes_.fill(0); }
  explicit Key(const std::array<uint8_t, kKeySize>& bytes) : bytes_(bytes) {}
  Key(const Key&) = default;
  Key& operator=(const Key&) = default;
  ~Key();
  const uint8_t* data() const { return bytes_.data(); }
  uint8_t* data() { return bytes_.data(); }
  static constexpr size_t size() { return kKeySize; }
  static Key random();  // from the operating system's generator (libsodium's randombytes)

 private:
  std::array<uint8_t, kKeySize> bytes_;
};

// The key file's text for `key` (one line and a newline).
std::string format_key(const Key& key);
// Parses a key file's text; std::nullopt with a one-line reason in out_error for anything else.
std::optional<Key> parse_key(std::string_view text, std::string* out_error);

// Writes a new random key to `path`, created with mode 0600; refuses to overwrite an existing file.
// Returns the error (one line), or std::nullopt on success.
std::optional<std::string> generate_key_file(const std::string& path);
// Reads a key file. Refuses one that group or others may read (a shared secret must stay secret).
std::optional<Key> load_key_file(const std::string& path, std::string* out_error);

}  // namespace dhr::secure
