#include "net/peer_address.hpp"

#include <arpa/inet.h>

#include <charconv>
#include <cstring>

namespace dhr::net {
namespace {

bool parse_port(std::string_view text, uint16_t& out_port) {
  if (text.empty() || text.size() > 5) return false;
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value == 0 || value > 65535) return false;
  out_port = static_cast<uint16_t>(value);
  return true;
}

}  // namespace

PeerAddress PeerAddress::ipv4(const std::array<uint8_t, 4>& bytes, uint16_t port) {
  PeerAddress address;
  std::memcpy(address.bytes_.data(), bytes.data(), bytes.size());
  address.port_ = port;
  address.family_ = Family::kIpv4;
  return address;
}

PeerAddress PeerAddress::ipv6(const std::array<uint8_t, 16>& bytes, uint16_t port, uint32_t scope_id) {
  PeerAddress address;
  address.bytes_ = bytes;
  address.port_ = port;
  address.scope_id_ = scope_id;
  address.family_ = Family::kIpv6;
  return address;
}

std::optional<PeerAddress> PeerAddress::parse(std::string_view text) {
  std::string host;
  uint16_t port = 0;
  if (!split_host_port(text, host, port)) return std::nullopt;
  std::array<uint8_t, 16> bytes{};
  if (inet_pton(AF_INET, host.c_str(), bytes.data()) == 1) {
    return ipv4({bytes[0], bytes[1], bytes[2], bytes[3]}, port);
  }
  uint32_t scope_id = 0;
  const size_t percent = host.find('%');
  if (percent != std::string::npos) {
    const std::string_view scope = std::string_view(host).substr(percent + 1);
    const auto [end, ec] = std::from_chars(scope.data(), scope.data() + scope.size(), scope_id);
    if (scope.empty() || ec != std::errc() || end != scope.data() + scope.size()) return std::nullopt;
    host.resize(percent);
  }
  if (inet_pton(AF_INET6, host.c_str(), bytes.data()) == 1) return ipv6(bytes, port, scope_id);
  return std::nullopt;
}

std::string PeerAddress::address_string() const {
  char text[INET6_ADDRSTRLEN + 16] = {};
  switch (family_) {
    case Family::kIpv4:
      inet_ntop(AF_INET, bytes_.data(), text, sizeof(text));
      return text;
    case Family::kIpv6: {
      inet_ntop(AF_INET6, bytes_.data(), text, sizeof(text));
      std::string result = text;
      if (scope_id_ != 0) result += "%" + std::to_string(scope_id_);
      return result;
    }
    case Family::kNone:
      break;
  }
  return "<none>";
}

std::string PeerAddress::to_string() const {
  switch (family_) {
    case Family::kIpv4:
      return address_string() + ":" + std::to_string(port_);
    case Family::kIpv6:
      return "[" + address_string() + "]:" + std::to_string(port_);
    case Family::kNone:
      break;
  }
  return "<none>";
}

bool PeerAddress::is_loopback() const {
  if (family_ == Family::kIpv4) return bytes_[0] == 127;
  if (family_ == Family::kIpv6) {
    for (size_t i = 0; i < 15; ++i) {
      if (bytes_[i] != 0) return false;
    }
    return bytes_[15] == 1;
  }
  return false;
}

size_t PeerAddress::hash() const {
  // FNV-1a over every field: cheap, and peers are few.
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](uint8_t byte) {
    h ^= byte;
    h *= 1099511628211ull;
  };
  for (uint8_t byte : bytes_) mix(byte);
  for (int shift = 0; shift < 32; shift += 8) mix(static_cast<uint8_t>(scope_id_ >> shift));
  mix(static_cast<uint8_t>(port_));
  mix(static_cast<uint8_t>(port_ >> 8));
  mix(static_cast<uint8_t>(family_));
  return static_cast<size_t>(h);
}

bool split_host_port(std::string_view text, std::string& out_host, uint16_t& out_port,
                     uint16_t default_port) {
  if (text.empty()) return false;
  std::string_view host;
  std::string_view port;
  bool has_port = false;
  if (text.front() == '[') {
    const size_t close = text.find(']');
    if (close == std::string_view::npos) return false;
    host = text.substr(1, close - 1);
    const std::string_view rest = text.substr(close + 1);
    if (!rest.empty()) {
      if (rest.front() != ':') return false;
      port = rest.substr(1);
      has_port = true;
    }
  } else {
    const size_t first_colon = text.find(':');
    const size_t last_colon = text.rfind(':');
    if (first_colon != last_colon) {
      host = text;  // bare IPv6 literal: no port possible without brackets
    } else if (first_colon != std::string_view::npos) {
      host = text.substr(0, first_colon);
      port = text.substr(first_colon + 1);
      has_port = true;
    } else {
      host = text;
    }
  }
  if (host.empty()) return false;
  for (char c : host) {
    if (static_cast<unsigned char>(c) <= ' ' || c == '[' || c == ']' || c == '/') return false;
  }
  uint16_t value = default_port;
  if (has_port) {
    if (!parse_port(port, value)) return false;
  } else if (default_port == 0) {
    return false;
  }
  out_host.assign(host);
  out_port = value;
  return true;
}

}  // namespace dhr::net
