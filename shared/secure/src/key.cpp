#include "secure/key.hpp"

#include "sodium_init.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace dhr::secure {
namespace {

constexpr std::string_view kKeyTag = "dhr-xr-key-1";
constexpr size_t kMaxKeyFileSize = 4096;

bool fail(std::string* out_error, const std::string& text) {
  if (out_error != nullptr) *out_error = text;
  return false;
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

Key::~Key() { sodium_memzero(bytes_.data(), bytes_.size()); }

Key Key::random() {
  ensure_sodium();
  Key key;
  randombytes_buf(key.data(), kKeySize);
  return key;
}

std::string format_key(const Key& key) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out(kKeyTag);
  out += ' ';
  for (size_t i = 0; i < kKeySize; ++i) {
    out += kHex[key.data()[i] >> 4];
    out += kHex[key.data()[i] & 15];
  }
  out += '\n';
  return out;
}

std::optional<Key> parse_key(std::string_view text, std::string* out_error) {
  std::optional<Key> found;
  size_t line_number = 0;
  while (!text.empty()) {
    const size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    const std::string where = "line " + std::to_string(line_number) + ": ";
    if (found) {
      fail(out_error, where + "more than one key");
      return std::nullopt;
    }
    if (line.substr(0, kKeyTag.size()) != kKeyTag || line.size() < kKeyTag.size() + 1 ||
        line[kKeyTag.size()] != ' ') {
      fail(out_error, where + "expected \"" + std::string(kKeyTag) + " <64 hex digits>\"");
      return std::nullopt;
    }
    const std::string_view hex = line.substr(kKeyTag.size() + 1);
    if (hex.size() != 2 * kKeySize) {
      fail(out_error, where + "the key has " + std::to_string(hex.size()) + " hex digits, expected 64");
      return std::nullopt;
    }
    Key key;
    for (size_t i = 0; i < kKeySize; ++i) {
      const int hi = hex_value(hex[2 * i]), lo = hex_value(hex[2 * i + 1]);
      if (hi < 0 || lo < 0) {
        fail(out_error, where + "the key has a character that is not a hex digit");
        return std::nullopt;
      }
      key.data()[i] = static_cast<uint8_t>(hi * 16 + lo);
    }
    found = key;
  }
  if (!found) fail(out_error, "no key in the file");
  return found;
}

std::optional<std::string> generate_key_file(const std::string& path) {
  const Key key = Key::random();
  const std::string text = format_key(key);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) {
    if (errno == EEXIST) return path + " exists; not overwriting a key (remove it first)";
    return "cannot create " + path + ": " + std::strerror(errno);
  }
  const ssize_t written = ::write(fd, text.data(), text.size());
  const bool ok = written == static_cast<ssize_t>(text.size()) && ::fsync(fd) == 0;
  ::close(fd);
  if (!ok) {
    ::unlink(path.c_str());
    return "cannot write " + path;
  }
  return std::nullopt;
}

std::optional<Key> load_key_file(const std::string& path, std::string* out_error) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    fail(out_error, "cannot read key file " + path + ": " + std::strerror(errno));
    return std::nullopt;
  }
  if (!S_ISREG(st.st_mode)) {
    fail(out_error, "key file " + path + " is not a regular file");
    return std::nullopt;
  }
  if ((st.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    fail(out_error, "key file " + path + " may be read by others (mode " + mode + "); run: chmod 600 " + path);
    return std::nullopt;
  }
  if (st.st_size > static_cast<off_t>(kMaxKeyFileSize)) {
    fail(out_error, "key file " + path + " is larger than " + std::to_string(kMaxKeyFileSize) + " bytes");
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in.good() && !in.eof()) {
    fail(out_error, "cannot read key file " + path);
    return std::nullopt;
  }
  std::string error;
  std::string content = text.str();
  std::optional<Key> key = parse_key(content, &error);
  sodium_memzero(content.data(), content.size());
  if (!key) fail(out_error, "key file " + path + ": " + error);
  return key;
}

}  // namespace dhr::secure
