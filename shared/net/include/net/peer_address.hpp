// PeerAddress: an IPv4 or IPv6 UDP endpoint (address + port) as a plain value, so headers and session
// tables can name peers without including Asio. Comparable and hashable (key of a session map).
#pragma once
#include <array>
#include <compare>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace dhr::net {

class PeerAddress {
 public:
  enum class Family : uint8_t { kNone = 0, kIpv4 = 4, kIpv6 = 6 };

  PeerAddress() = default;  // invalid (Family::kNone)
  static PeerAddress ipv4(const std::array<uint8_t, 4>& bytes, uint16_t port);
  static PeerAddress ipv6(const std::array<uint8_t, 16>& bytes, uint16_t port, uint32_t scope_id = 0);
  static PeerAddress loopback_ipv4(uint16_t port) { return ipv4({127, 0, 0, 1}, port); }

  // Numeric forms only, no name lookup: "127.0.0.1:4000", "[::1]:4000", "[fe80::1%2]:4000".
  // nullopt on anything else (missing port, port 0 or > 65535, junk).
  static std::optional<PeerAddress> parse(std::string_view text);

  std::string to_string() const;       // "127.0.0.1:4000", "[::1]:4000"; "<none>" when invalid
  std::string address_string() const;  // without the port: "127.0.0.1", "::1"

  Family family() const { return family_; }
  bool valid() const { return family_ != Family::kNone; }
  bool is_ipv4() const { return family_ == Family::kIpv4; }
  bool is_ipv6() const { return family_ == Family::kIpv6; }
  uint16_t port() const { return port_; }
  uint32_t scope_id() const { return scope_id_; }
  // IPv4: the first 4 bytes are used, the rest are zero.
  const std::array<uint8_t, 16>& bytes() const { return bytes_; }
  std::array<uint8_t, 4> ipv4_bytes() const { return {bytes_[0], bytes_[1], bytes_[2], bytes_[3]}; }
  bool is_loopback() const;

  size_t hash() const;
  auto operator<=>(const PeerAddress&) const = default;

 private:
  std::array<uint8_t, 16> bytes_{};
  uint32_t scope_id_ = 0;
  uint16_t port_ = 0;
  Family family_ = Family::kNone;
};

struct PeerAddressHash {
  size_t operator()(const PeerAddress& address) const { return address.hash(); }
};

// Splits "host:port", "[v6]:port" (or "v6-literal" with no port only when default_port != 0) into host
// and port. The host may be a name ("localhost"); no lookup happens here. False on malformed input.
bool split_host_port(std::string_view text, std::string& out_host, uint16_t& out_port,
                     uint16_t default_port = 0);

}  // namespace dhr::net
