#include "net/endpoints.hpp"

#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace dhr::net {

std::vector<PeerAddress> resolve_host(const std::string& host, uint16_t port, std::string* out_error) {
  std::vector<PeerAddress> v4;
  std::vector<PeerAddress> v6;
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_protocol = IPPROTO_UDP;
  addrinfo* results = nullptr;
  const int rc = getaddrinfo(host.c_str(), nullptr, &hints, &results);
  if (rc != 0) {
    if (out_error) *out_error = "cannot resolve '" + host + "': " + gai_strerror(rc);
    return {};
  }
  for (const addrinfo* info = results; info != nullptr; info = info->ai_next) {
    if (info->ai_family == AF_INET && info->ai_addrlen >= sizeof(sockaddr_in)) {
      sockaddr_in address{};
      std::memcpy(&address, info->ai_addr, sizeof(address));
      std::array<uint8_t, 4> bytes{};
      std::memcpy(bytes.data(), &address.sin_addr, bytes.size());
      v4.push_back(PeerAddress::ipv4(bytes, port));
    } else if (info->ai_family == AF_INET6 && info->ai_addrlen >= sizeof(sockaddr_in6)) {
      sockaddr_in6 address{};
      std::memcpy(&address, info->ai_addr, sizeof(address));
      std::array<uint8_t, 16> bytes{};
      std::memcpy(bytes.data(), &address.sin6_addr, bytes.size());
      v6.push_back(PeerAddress::ipv6(bytes, port, address.sin6_scope_id));
    }
  }
  freeaddrinfo(results);
  std::vector<PeerAddress> all;
  for (const std::vector<PeerAddress>* family : {&v4, &v6}) {
    for (const PeerAddress& address : *family) {
      if (std::find(all.begin(), all.end(), address) == all.end()) all.push_back(address);
    }
  }
  if (all.empty() && out_error) *out_error = "'" + host + "' has no IPv4 or IPv6 address";
  return all;
}

void ServerEndpoint::start(const ServerEndpointConfig& config, DatagramHandler handler) {
  UdpSocketConfig socket_config;
  socket_config.bind_address = config.bind_address;
  socket_config.port = config.port;
  socket_config.max_datagram_size = config.max_datagram_size;
  socket_config.max_pending_sends = config.max_pending_sends;
  socket_config.receive_buffer_bytes = 4 << 20;  // several clients' poses arrive together
  socket_config.send_buffer_bytes = 4 << 20;     // a frame's shards leave in one burst
  socket_.open(socket_config, std::move(handler));
}

void ClientEndpoint::connect(const ClientEndpointConfig& config, DatagramHandler handler) {
  if (config.server_port == 0) throw std::runtime_error("client endpoint: server port 0 is not valid");
  std::string error;
  const std::vector<PeerAddress> candidates = resolve_host(config.server_host, config.server_port, &error);
  if (candidates.empty()) throw std::runtime_error("client endpoint: " + error);
  const PeerAddress server = candidates.front();

  UdpSocketConfig socket_config;
  socket_config.bind_address = server.is_ipv4() ? "0.0.0.0" : "::";
  socket_config.port = 0;
  socket_config.max_datagram_size = config.max_datagram_size;
  socket_config.max_pending_sends = config.max_pending_sends;
  socket_config.receive_buffer_bytes = 4 << 20;  // a visibility frame arrives as a burst of shards
  if (config.accept_only_from_server) socket_config.accept_only_from = server;
  socket_.open(socket_config, std::move(handler));
  server_ = server;
}

}  // namespace dhr::net
