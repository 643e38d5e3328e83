// UdpVisibilityClient: a VisibilityClient on a real UDP socket (net::ClientEndpoint, which receives on
// its own thread and accepts datagrams only from the server), on the monotonic clock, with an optional
// ImpairedSender in front of the socket (--net-* options: this side impairs what it sends).
// The executable's render loop calls client().tick(), send_pose() and take_newest().
#pragma once
#include "net/clock.hpp"
#include "net/endpoints.hpp"
#include "net/impaired_sender.hpp"
#include "net/impairment.hpp"
#include "link/visibility_client.hpp"

#include <memory>
#include <optional>
#include <string>

namespace dhr::client {

class UdpVisibilityClient {
 public:
  UdpVisibilityClient() = default;
  ~UdpVisibilityClient();  // close()
  UdpVisibilityClient(const UdpVisibilityClient&) = delete;
  UdpVisibilityClient& operator=(const UdpVisibilityClient&) = delete;

  // Resolves the server, binds an ephemeral port and starts receiving; the handshake starts with the
  // first client().tick(). Throws std::runtime_error (host does not resolve, no socket) or
  // std::invalid_argument (bad config or impairment params), with a one-line message. Once only.
  void connect(const VisibilityClientConfig& config, const std::string& host, uint16_t port,
               const net::ImpairmentParams& impairment = {});
  // Sends Bye when connected, lets the impairment layer release it (bounded wait), stops the socket.
  // Idempotent.
  void close();

  bool is_open() const { return client_ != nullptr; }
  VisibilityClient& client() { return *client_; }
  const VisibilityClient& client() const { return *client_; }
  const net::Clock& clock() const { return clock_; }
  net::UdpCounters udp_counters() const { return endpoint_.counters(); }
  std::optional<net::ImpairedSenderStats> impairment_stats() const;
  const net::PeerAddress& server_address() const { return endpoint_.server_address(); }
  uint16_t local_port() const { return endpoint_.local_port(); }

 private:
  // Sends to the connected server whatever address it is given (the VisibilityClient does not know it).
  class ToServer final : public net::DatagramSender {
   public:
    explicit ToServer(net::ClientEndpoint& endpoint) : endpoint_(endpoint) {}
    bool send_to(std::span<const uint8_t> datagram, const net::PeerAddress&) override {
      return endpoint_.send(datagram);
    }

   private:
    net::ClientEndpoint& endpoint_;
  };

  net::SteadyClock clock_;
  net::ClientEndpoint endpoint_;
  ToServer to_server_{endpoint_};
  std::unique_ptr<net::ImpairedSender> impaired_;
  std::unique_ptr<VisibilityClient> client_;
};

}  // namespace dhr::client
