// The two roles over UdpSocket:
//  - ServerEndpoint: one socket serving any number of clients at once. Every datagram reaches the
//    handler with its sender's PeerAddress; replies go to a given peer. Sessions (tokens) live above.
//  - ClientEndpoint: resolves the server's host name, binds an ephemeral port and accepts datagrams only
//    from the server (anything else is counted as dropped_foreign). Receives on its own thread.
// Hand received data to the render loop through LatestSlot (net/latest_slot.hpp).
#pragma once
#include "net/peer_address.hpp"
#include "net/udp_socket.hpp"

#include <string>
#include <vector>

namespace dhr::net {

// Name or numeric literal -> UDP addresses (getaddrinfo, blocking: setup code only). IPv4 results come
// first (a server bound to 0.0.0.0 is not reachable over ::1), then IPv6, duplicates removed. Empty on
// failure, with the reason in *out_error when given.
std::vector<PeerAddress> resolve_host(const std::string& host, uint16_t port, std::string* out_error = nullptr);

struct ServerEndpointConfig {
  std::string bind_address = "0.0.0.0";  // "::" for IPv6 and IPv4 peers, "127.0.0.1" for loopback only
  uint16_t port = 0;                     // 0: ephemeral (tests)
  size_t max_datagram_size = kDefaultMaxDatagramSize;
  size_t max_pending_sends = 16384;      // a frame is many shards, times several clients
};

class ServerEndpoint final : public DatagramSender {
 public:
  ServerEndpoint() = default;
  ~ServerEndpoint() override = default;  // the socket stops itself

  // Throws std::runtime_error when the address cannot be bound (message names address and reason).
  void start(const ServerEndpointConfig& config, DatagramHandler handler);
  void stop() { socket_.stop(); }
  bool running() const { return socket_.running(); }
  uint16_t port() const { return socket_.local_port(); }
  PeerAddress local_address() const { return socket_.local_address(); }

  bool send_to(std::span<const uint8_t> datagram, const PeerAddress& peer) override {
    return socket_.send_to(datagram, peer);
  }
  UdpCounters counters() const { return socket_.counters(); }

 private:
  UdpSocket socket_;
};

struct ClientEndpointConfig {
  std::string server_host = "127.0.0.1";  // name ("localhost") or IPv4/IPv6 literal
  uint16_t server_port = 0;
  size_t max_datagram_size = kDefaultMaxDatagramSize;
  size_t max_pending_sends = 1024;
  bool accept_only_from_server = true;
};

class ClientEndpoint final : public DatagramSender {
 public:
  ClientEndpoint() = default;
  ~ClientEndpoint() override = default;

  // Resolves the server, binds an ephemeral local port of the same address family and starts the
  // receive thread. UDP has no connection: nothing is sent here. Throws std::runtime_error when the
  // host does not resolve or no socket can be bound.
  void connect(const ClientEndpointConfig& config, DatagramHandler handler);
  void stop() { socket_.stop(); }
  bool running() const { return socket_.running(); }

  // To the server (fire and forget).
  bool send(std::span<const uint8_t> datagram) { return socket_.send_to(datagram, server_); }
  bool send_to(std::span<const uint8_t> datagram, const PeerAddress& peer) override {
    return socket_.send_to(datagram, peer);
  }

  const PeerAddress& server_address() const { return server_; }
  uint16_t local_port() const { return socket_.local_port(); }
  UdpCounters counters() const { return socket_.counters(); }

 private:
  UdpSocket socket_;
  PeerAddress server_;
};

}  // namespace dhr::net
